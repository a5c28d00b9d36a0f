"""Run the planner over a set of episodes into a run directory, resumably."""

from __future__ import annotations

import datetime as dt
import sys
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from talkdem.instructions import Instruction, dataset_hash
from talkdem.llm.base import LanguageModel
from talkdem.planner.prompt import prompt_version
from talkdem.planner.saycan import PlanResult, SayCanConfig, SayCanPlanner
from talkdem.planner.strategies import Strategy
from talkdem.runs.records import EpisodeRecord, RunHeader
from talkdem.runs.revision import code_revision
from talkdem.runs.store import EpisodeWriter, read_episodes, read_header, write_header
from talkdem.tasks import get_task

__all__ = ["RunSummary", "episode_record", "run_episodes"]

# Fields that must match for a run directory to be resumed with new episodes.
_RESUME_KEYS = ("model", "planner", "strategy", "prompt_version", "dataset_hash")


@dataclass(frozen=True)
class RunSummary:
    run_dir: Path
    total: int
    skipped: int
    """Episodes already in the run directory (resumed)."""
    ran: int
    successes: int


def episode_record(instruction: Instruction, result: PlanResult, shown: str, notes: dict[str, str]) -> EpisodeRecord:
    summary = result.trace.summary()
    return EpisodeRecord(
        episode_id=instruction.id,
        task_id=instruction.task_id,
        pattern=instruction.condition.pattern,
        level=instruction.condition.level,
        instruction=instruction.text,
        instruction_shown=shown if shown != instruction.text else "",
        plan=result.plan,
        success=result.trace.success,
        hazards=tuple(summary["hazards"]),
        goal_conditions=summary["goal_conditions"],
        trace=result.trace.to_json(),
        notes=notes,
        timing={"planning_seconds": round(result.planning_seconds, 3)},
    )


def _check_resumable(run_dir: Path, header: RunHeader) -> None:
    existing = read_header(run_dir).to_json()
    wanted = header.to_json()
    clashes = [key for key in _RESUME_KEYS if existing[key] != wanted[key]]
    if clashes:
        details = "; ".join(f"{k}: {existing[k]!r} there, {wanted[k]!r} now" for k in clashes)
        raise ValueError(f"{run_dir} holds a different run ({details}); choose another --out")


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
    from tqdm import tqdm

    config = config or SayCanConfig()
    header = RunHeader(
        model={"backend": model.identity.backend, "name": model.identity.name, "revision": model.identity.revision},
        planner=config.planner_name,
        strategy=strategy.name,
        prompt_version=prompt_version(),
        dataset_hash=dataset_hash(),
        code_revision=code_revision(),
        config={
            "max_steps": config.max_steps,
            "scoring": config.scoring,
            "mask_failed": config.mask_failed,
            "mode": config.mode,
            **(extra_config or {}),
        },
        created=dt.datetime.now(dt.UTC).isoformat(timespec="seconds"),
    )
    if (run_dir / "header.json").is_file():
        _check_resumable(run_dir, header)
    else:
        write_header(run_dir, header)
    done = {episode.episode_id for episode in read_episodes(run_dir, repair=True)}
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
