"""Run the planner over a set of episodes into a run directory, resumably, one or several episodes at a time.

With `talkdem run --concurrency N`, N episodes are in flight at once (`talkdem.runs.scheduler`): each round the
model gets the pending request of every one of them together (a multi-sequence llama.cpp context runs them in
shared decodes; N clients of a served model send them at once, an episode staying on one server). Finished
episodes are appended as they finish, in whatever order that is, so a kill loses none of them; once every
episode of the selection is on disk the file is rewritten (atomically) in the selection's order, so a finished
run's `episodes.jsonl` is the same whatever the concurrency and the order of completion. Buffering and writing
in order instead would lose up to N-1 finished episodes on a kill.
"""

from __future__ import annotations

import contextlib
import dataclasses
import json
import sys
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING

from talkdem.instructions import Instruction
from talkdem.llm.interface.base import LanguageModel
from talkdem.planner.react import ReActConfig, ReActPlanner
from talkdem.planner.saycan import PlanResult, SayCanConfig, SayCanPlanner
from talkdem.planner.stepping import EpisodeSteps
from talkdem.planner.strategies import PlannerInput, Strategy
from talkdem.runs.records import EpisodeRecord
from talkdem.runs.runtime import sitting_runtime
from talkdem.runs.scheduler import ClientPool, in_flight
from talkdem.runs.spec import RESUME_KEYS, RunSpec, Scalar
from talkdem.runs.store import (
    EPISODES_FILE,
    HEADER_FILE,
    EpisodeWriter,
    finish_status,
    open_run,
    read_episodes,
    run_lock,
    set_status,
)
from talkdem.tasks import get_task

if TYPE_CHECKING:
    from talkdem.clarify import SimulatedPerson
    from talkdem.tasks import Task

__all__ = ["RESUME_KEYS", "RunSummary", "episode_record", "person_for", "run_episodes"]


@dataclass(frozen=True)
class RunSummary:
    run_dir: Path
    total: int
    skipped: int
    """Episodes already in the run directory (resumed)."""
    ran: int
    successes: int


def episode_record(
    instruction: Instruction, result: PlanResult, shown: str, notes: dict[str, str], *, thoughts: bool = False
) -> EpisodeRecord:
    if result.top_candidates:
        # `--log-top N`: each step's best skills and scores, kept in the record (notes hold text, so JSON)
        # for the viewer; a log alone would be lost with the terminal.
        top = [[[skill, round(score, 4)] for skill, score in step] for step in result.top_candidates]
        notes = {**notes, "top_candidates": json.dumps(top, ensure_ascii=False)}
    record = EpisodeRecord.from_trace(
        instruction,
        result.plan,
        result.trace,
        shown=shown,
        notes=notes,
        timing={"planning_seconds": round(result.planning_seconds, 3)},
    )
    if thoughts:  # ReAct: the thought before each step, beside the steps it led to
        record = dataclasses.replace(record, trace={**record.trace, "thoughts": list(result.generated)})
    return record.with_dialogue(result.dialogue) if result.dialogue is not None else record


Planner = SayCanPlanner | ReActPlanner


def person_for(config: SayCanConfig | ReActConfig, instruction: Instruction, task: Task) -> SimulatedPerson | None:
    """The simulated person who answers this episode's questions (None without clarification)."""
    if config.clarify == "none":
        return None
    from talkdem.clarify import SimulatedPerson

    return SimulatedPerson(config.clarify, instruction, task)


def _planner(model: LanguageModel, config: SayCanConfig | ReActConfig) -> Planner:
    if isinstance(config, ReActConfig):
        return ReActPlanner(model, config)
    return SayCanPlanner(model, config)


def run_episodes(
    instructions: Sequence[Instruction],
    model: LanguageModel,
    strategy: Strategy,
    run_dir: Path,
    config: SayCanConfig | ReActConfig | None = None,
    extra_config: dict[str, object] | None = None,
    progress: bool = True,
    clients: Sequence[LanguageModel] = (),
    *,
    concurrency: int = 1,
    backend_args: dict[str, Scalar] | None = None,
    new_revision_ok: bool = False,
) -> RunSummary:
    """Plan and execute every instruction not yet in `run_dir`; each finished episode is on disk at once.

    `concurrency`: episodes in flight at once (`talkdem.runs.scheduler`); `clients`: several clients of one served
    model (at least `concurrency` of them is not needed: an episode's requests go to client `slot % clients`;
    `model` is used for the header and the strategies' rewriting); empty: `model` alone.
    `extra_config`: the selection (conditions, sample size, shard) recorded in the header; `backend_args`:
    how the model was reached. The run's spec (`RunSpec`) writes the header and decides what a resume must
    match; `new_revision_ok` lets a run started on another code revision go on (both are recorded).
    """
    config = config or SayCanConfig()
    clients = list(clients) or [model]
    concurrency = max(concurrency, len(clients))
    served: dict[str, object] = {k: v for k, v in model.run_info().items() if k != "base_url"}
    if served:
        served["servers"] = sorted({c.run_info().get("base_url", "") for c in clients})
    spec = RunSpec.for_run(
        config,
        strategy,
        backend_args={"backend": model.identity.backend, **(backend_args or {})},
        selection=extra_config,
    )
    header = spec.header(
        model=model.identity.to_header(),
        planned_episodes=len(instructions),
        served=served,
        runtime=sitting_runtime(model) if not served else None,  # a served model's numbers come from its server
    )
    is_new = not run_dir.exists()
    try:
        with run_lock(run_dir):
            done = {
                episode.episode_id
                for episode in open_run(run_dir, header, spec.resume_keys, new_revision_ok=new_revision_ok)
            }
            try:
                summary = _run_locked(
                    instructions, done, model, clients, strategy, run_dir, config, progress, concurrency
                )
            except BaseException:
                if (run_dir / HEADER_FILE).is_file():
                    set_status(run_dir, "incomplete")
                raise
            finish_status(run_dir, [i.id for i in instructions])
            return summary
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
    done: set[str],
    model: LanguageModel,
    clients: Sequence[LanguageModel],
    strategy: Strategy,
    run_dir: Path,
    config: SayCanConfig | ReActConfig,
    progress: bool,
    concurrency: int,
) -> RunSummary:
    from tqdm import tqdm

    pending = [i for i in instructions if i.id not in done]
    stepping = ClientPool(clients) if len(clients) > 1 else model
    planner = _planner(stepping, config)
    successes = 0
    bar = tqdm(
        total=len(instructions),
        initial=len(instructions) - len(pending),
        unit="ep",
        disable=not progress,
        file=sys.stderr,
        desc=f"{strategy.name}",
    )
    Job = tuple[Instruction, PlannerInput]

    def jobs() -> Iterator[tuple[Job, Callable[[], EpisodeSteps[PlanResult]]]]:
        # Strategies batch their rewriting per chunk; chunks are read as slots free up, so the episodes of one
        # chunk are still in flight while the next is prepared. Small chunks keep a serial run's resume granular.
        chunk = 16 if concurrency == 1 else 8 * concurrency
        for start in range(0, len(pending), chunk):
            batch = pending[start : start + chunk]
            prepared = list(zip(batch, strategy.prepare([i.text for i in batch], model), strict=True))
            if concurrency > 1:
                # Episodes whose prompts begin alike run side by side, so a backend that reuses cached prefixes
                # (the multi-sequence llama.cpp scorer) finds the shared CARE demonstrations in flight.
                prepared.sort(key=lambda job: planner.prompt_for(job[1]))
            for instruction, planner_input in prepared:
                task = get_task(instruction.task_id)
                person = person_for(config, instruction, task)
                yield (instruction, planner_input), partial(planner.episode, task, planner_input, person)

    try:
        with EpisodeWriter(run_dir) as writer:
            for (instruction, planner_input), result in in_flight(jobs(), stepping, concurrency):
                writer.write(
                    episode_record(
                        instruction,
                        result,
                        planner_input.instruction,
                        planner_input.notes,
                        thoughts=isinstance(config, ReActConfig),
                    )
                )
                successes += result.trace.success
                bar.update(1)
                bar.set_postfix(success=f"{successes}/{bar.n - (len(instructions) - len(pending))}")
    finally:
        if isinstance(stepping, ClientPool):
            stepping.close()
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
