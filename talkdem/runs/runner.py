"""Run the planner over a set of episodes into a run directory, resumably, one or several episodes at a time.

With several model clients (`talkdem run --concurrency N`, a served backend), N episodes step at once, each
on one client from its first step to its last (so an episode stays on one server), each step's candidates in
one request. Finished episodes are appended as they finish, in whatever order that is, so a kill loses none
of them; once every episode of the selection is on disk the file is rewritten (atomically) in the selection's
order, so a finished run's `episodes.jsonl` is the same whatever the concurrency and the order of completion.
Buffering and writing in order instead would lose up to N-1 finished episodes on a kill.
"""

from __future__ import annotations

import contextlib
import queue
import sys
from collections.abc import Sequence
from concurrent.futures import FIRST_COMPLETED, Future, ThreadPoolExecutor, wait
from dataclasses import dataclass
from pathlib import Path

from talkdem.instructions import Instruction
from talkdem.llm.base import LanguageModel
from talkdem.planner.prompt import prompt_version
from talkdem.planner.saycan import PlanResult, SayCanConfig, SayCanPlanner
from talkdem.planner.strategies import PlannerInput, Strategy
from talkdem.runs.records import OUTCOME_KEYS, EpisodeRecord, RunHeader
from talkdem.runs.store import EPISODES_FILE, HEADER_FILE, EpisodeWriter, open_run, read_episodes, run_lock
from talkdem.tasks import get_task

__all__ = ["RESUME_KEYS", "RunSummary", "episode_record", "run_episodes"]

# What must match for a run directory to be resumed with new episodes: what an outcome means, and the shard
# (a shard's folder must not take another shard's episodes). The selection may grow between sittings.
RESUME_KEYS = (*OUTCOME_KEYS, "config.shard")


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
    clients: Sequence[LanguageModel] = (),
) -> RunSummary:
    """Plan and execute every instruction not yet in `run_dir`; each finished episode is on disk at once.

    `clients`: the model clients that step episodes at once (one episode per client at a time; `model` is
    used for the header and the strategies' rewriting); empty: `model` alone, one episode at a time.
    """
    config = config or SayCanConfig()
    clients = list(clients) or [model]
    served: dict[str, object] = {k: v for k, v in model.run_info().items() if k != "base_url"}
    if served:
        served["servers"] = sorted({c.run_info().get("base_url", "") for c in clients})
    header = RunHeader.new(
        model={"backend": model.identity.backend, "name": model.identity.name, "revision": model.identity.revision},
        planner=config.planner_name,
        strategy=strategy.name,
        # What a run sets that changes a rendered prompt names the prompt version too.
        prompt_version=prompt_version({"failure_message": config.failure_message, "strategy_args": strategy.options()}),
        config={
            "max_steps": config.max_steps,
            "scoring": config.scoring,
            "mask_failed": config.mask_failed,
            "failure_message": config.failure_message,
            "feedback": config.feedback,
            "mode": config.mode,
            "strategy_args": strategy.options(),
            **(extra_config or {}),
            **({"served": served} if served else {}),
            "planned_episodes": len(instructions),
        },
    )
    is_new = not run_dir.exists()
    try:
        with run_lock(run_dir):
            return _run_locked(instructions, model, clients, strategy, run_dir, header, config, progress)
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
    clients: Sequence[LanguageModel],
    strategy: Strategy,
    run_dir: Path,
    header: RunHeader,
    config: SayCanConfig,
    progress: bool,
) -> RunSummary:
    from tqdm import tqdm

    done = {episode.episode_id for episode in open_run(run_dir, header, RESUME_KEYS)}
    pending = [i for i in instructions if i.id not in done]
    planners: queue.SimpleQueue[SayCanPlanner] = queue.SimpleQueue()
    for client in clients:
        planners.put(SayCanPlanner(client, config))
    successes = 0
    bar = tqdm(
        total=len(instructions),
        initial=len(instructions) - len(pending),
        unit="ep",
        disable=not progress,
        file=sys.stderr,
        desc=f"{strategy.name}",
    )

    def plan_one(instruction: Instruction, planner_input: PlannerInput) -> PlanResult:
        planner = planners.get()  # a free client: the whole episode runs on it
        try:
            return planner.plan(get_task(instruction.task_id), planner_input)
        finally:
            planners.put(planner)

    chunk = 16 * len(clients)  # strategies batch their generation requests; small chunks keep resume granular
    with EpisodeWriter(run_dir) as writer, ThreadPoolExecutor(max_workers=len(clients)) as pool:
        for start in range(0, len(pending), chunk):
            batch = pending[start : start + chunk]
            inputs = strategy.prepare([i.text for i in batch], model)
            running: dict[Future[PlanResult], tuple[Instruction, PlannerInput]] = {
                pool.submit(plan_one, instruction, planner_input): (instruction, planner_input)
                for instruction, planner_input in zip(batch, inputs, strict=True)
            }
            try:
                while running:
                    finished, _ = wait(running, return_when=FIRST_COMPLETED)
                    for future in finished:
                        instruction, planner_input = running.pop(future)
                        result = future.result()
                        writer.write(
                            episode_record(instruction, result, planner_input.instruction, planner_input.notes)
                        )
                        successes += result.trace.success
                        bar.update(1)
                        bar.set_postfix(success=f"{successes}/{bar.n - (len(instructions) - len(pending))}")
            except BaseException:
                for future in running:
                    future.cancel()
                raise
    bar.close()
    _order_when_complete(run_dir, instructions)
    return RunSummary(run_dir, len(instructions), len(instructions) - len(pending), len(pending), successes)


def _order_when_complete(run_dir: Path, instructions: Sequence[Instruction]) -> None:
    """Rewrite a finished run's episodes in the selection's order (episodes from an earlier, larger selection
    keep their place after them)."""
    from talkdem.runs.shards import rewrite_episodes

    episodes = read_episodes(run_dir)
    by_id = {e.episode_id: e for e in episodes}
    wanted = [i.id for i in instructions]
    if not set(wanted) <= set(by_id):
        return
    chosen = set(wanted)
    ordered = [by_id[i] for i in wanted] + [e for e in episodes if e.episode_id not in chosen]
    if [e.episode_id for e in ordered] != [e.episode_id for e in episodes]:
        rewrite_episodes(run_dir, ordered)
