"""Run the planner over a set of episodes into a run directory, resumably."""

from __future__ import annotations

import contextlib
import sys
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from talkdem.instructions import Instruction
from talkdem.llm.base import LanguageModel
from talkdem.planner.prompt import prompt_version
from talkdem.planner.saycan import PlanResult, SayCanConfig, SayCanPlanner
from talkdem.planner.strategies import Strategy
from talkdem.runs.records import EpisodeRecord, RunHeader
from talkdem.runs.store import EPISODES_FILE, HEADER_FILE, EpisodeWriter, open_run, run_lock
from talkdem.tasks import get_task

__all__ = ["RESUME_KEYS", "RunSummary", "episode_record", "run_episodes"]

# What must match for a run directory to be resumed with new episodes: everything that changes what an
# episode's outcome means. The selection (conditions, sample size) may grow between sittings.
RESUME_KEYS = (
    "model",
    "planner",
    "strategy",
    "prompt_version",
    "dataset_hash",
    "config.max_steps",
    "config.scoring",
    "config.mask_failed",
    "config.mode",
)


@dataclass(frozen=True)
class RunSummary:
    run_dir: Path
    total: int
    skipped: int
    """Episodes already in the run directory (resumed)."""
    ran: int
    successes: int


def episode_record(instruction: Instruction, result: PlanResult, shown: str, notes: dict[str, str]) -> EpisodeRecord:
    return EpisodeRecord.from_trace(
        instruction,
        result.plan,
        result.trace,
        shown=shown,
        notes=notes,
        timing={"planning_seconds": round(result.planning_seconds, 3)},
    )


def run_episodes(
    instructions: Sequence[Instruction],
    model: LanguageModel,
    strategy: Strategy,
    run_dir: Path,
    config: SayCanConfig | None = None,
    extra_config: dict[str, object] | None = None,
    progress: bool = True,
) -> RunSummary:
    """Plan and execute every instruction not yet in `run_dir`; each finished episode is on disk at once."""
    config = config or SayCanConfig()
    header = RunHeader.new(
        model={"backend": model.identity.backend, "name": model.identity.name, "revision": model.identity.revision},
        planner=config.planner_name,
        strategy=strategy.name,
        prompt_version=prompt_version(),
        config={
            "max_steps": config.max_steps,
            "scoring": config.scoring,
            "mask_failed": config.mask_failed,
            "mode": config.mode,
            **(extra_config or {}),
            "planned_episodes": len(instructions),
        },
    )
    is_new = not run_dir.exists()
    try:
        with run_lock(run_dir):
            return _run_locked(instructions, model, strategy, run_dir, header, config, progress)
    except BaseException:
        if is_new:
            _remove_if_empty(run_dir)
        raise


def _remove_if_empty(run_dir: Path) -> None:
    """Undo a run directory this call created when not one episode finished (an unreachable server, a
    model that fails on the first step): an empty run would later resume as if it were this run."""
    episodes = run_dir / EPISODES_FILE
    if episodes.exists() and episodes.stat().st_size:
        return
    for name in (EPISODES_FILE, HEADER_FILE):
        (run_dir / name).unlink(missing_ok=True)
    with contextlib.suppress(OSError):  # not empty: something else put files there meanwhile
        run_dir.rmdir()


def _run_locked(
    instructions: Sequence[Instruction],
    model: LanguageModel,
    strategy: Strategy,
    run_dir: Path,
    header: RunHeader,
    config: SayCanConfig,
    progress: bool,
) -> RunSummary:
    from tqdm import tqdm

    done = {episode.episode_id for episode in open_run(run_dir, header, RESUME_KEYS)}
    pending = [i for i in instructions if i.id not in done]
    planner = SayCanPlanner(model, config)
    successes = 0
    bar = tqdm(
        total=len(instructions),
        initial=len(instructions) - len(pending),
        unit="ep",
        disable=not progress,
        file=sys.stderr,
        desc=f"{strategy.name}",
    )
    with EpisodeWriter(run_dir) as writer:
        # Strategies batch their generation requests; a batch per task keeps resume granularity small.
        for start in range(0, len(pending), 16):
            batch = pending[start : start + 16]
            inputs = strategy.prepare([i.text for i in batch], model)
            for instruction, planner_input in zip(batch, inputs, strict=True):
                result = planner.plan(get_task(instruction.task_id), planner_input)
                writer.write(episode_record(instruction, result, planner_input.instruction, planner_input.notes))
                successes += result.trace.success
                bar.update(1)
                bar.set_postfix(success=f"{successes}/{bar.n - (len(instructions) - len(pending))}")
    bar.close()
    return RunSummary(run_dir, len(instructions), len(instructions) - len(pending), len(pending), successes)
