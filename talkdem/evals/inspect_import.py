"""An inspect_ai log of the TALK-Dem task -> a TALK-Dem run directory (`talkdem import-inspect LOG --out RUN`).

Each scored sample becomes one `EpisodeRecord.from_trace`: the skills the agent executed (the sample's
`talkdem_plan` store entry) are stepped through the simulator seam again (deterministic, so this is the
episode the agent played), and an outcome that disagrees with the log's own score is refused, naming the
sample. Samples that errored are left out and counted; the header's `planned_episodes` is the log's sample
count, so such a run shows as incomplete. The header names the inspect model as the model, the solver as
the strategy, and the log by file name (never a machine path: headers are published).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

from talkdem.instructions import Instruction, load_instructions
from talkdem.plans import PlanFormatError, check_plan
from talkdem.runs.records import EpisodeRecord, RunHeader
from talkdem.runs.store import EpisodeWriter, open_run, run_lock
from talkdem.schema import parse_instruction_id

__all__ = ["INSPECT_RESUME_KEYS", "ImportSummary", "import_inspect_log"]

INSPECT_RESUME_KEYS = ("model", "planner", "strategy", "dataset_hash", "config.inspect")
_PLAN_KEY = "talkdem_plan"  # the inspect task's store key (talkdem.evals.inspect_task.PLAN_KEY)


@dataclass(frozen=True)
class ImportSummary:
    run_dir: Path
    imported: int
    errored: int
    """Samples the log holds with an error instead of a score (left out)."""
    successes: int


def _canonical(episode_id: object, where: str, known: dict[str, Instruction]) -> Instruction:
    if not isinstance(episode_id, str):
        raise ValueError(f"{where}: the sample has no TALK-Dem episode id")
    task_id, condition = parse_instruction_id(episode_id)
    canonical = f"{task_id}:{condition.pattern}:{condition.level}"
    if canonical not in known:
        raise ValueError(f"{where}: unknown episode id '{episode_id}'")
    return known[canonical]


def _logged_success(sample: Any, where: str) -> bool:
    scores = sample.scores or {}
    if "goal_check" not in scores:
        raise ValueError(f"{where}: no 'goal_check' score (is this a log of the TALK-Dem inspect task?)")
    value = scores["goal_check"].value
    if value not in ("C", "I"):
        raise ValueError(f"{where}: goal_check score {value!r} is neither C nor I")
    return bool(value == "C")


def import_inspect_log(log_path: Path, run_dir: Path) -> ImportSummary:
    """Write the log's episodes into `run_dir` (resuming an import of the same log's evaluation)."""
    try:
        from inspect_ai.log import read_eval_log
    except ImportError as exc:
        raise ImportError("importing an inspect log needs inspect_ai: pip install 'talkdem[inspect]'") from exc
    from talkdem.sim.seam import DEFAULT_MAX_STEPS, execute_plan, load_simulator
    from talkdem.tasks import get_task

    if not log_path.is_file():
        raise FileNotFoundError(f"{log_path}: inspect log not found")
    try:
        log = read_eval_log(str(log_path))
    except Exception as exc:  # inspect raises its own types for a file that is no log
        raise ValueError(f"{log_path}: not a readable inspect log ({type(exc).__name__}: {exc})") from None
    spec = log.eval
    max_steps = int(spec.task_args.get("max_steps", DEFAULT_MAX_STEPS))
    solver = spec.solver or "talkdem_agent"
    header = RunHeader.new(
        model={"backend": "inspect", "name": spec.model, "revision": ""},
        planner="external",
        strategy=solver,
        prompt_version="",
        config={
            "inspect": {"task": spec.task, "eval_id": spec.eval_id, "task_args": dict(spec.task_args)},
            "log": log_path.name,
            "max_steps": max_steps,
            "planned_episodes": int(spec.dataset.samples or len(log.samples or [])),
        },
    )
    known = {i.id: i for i in load_instructions()}
    backend = load_simulator()
    imported = errored = successes = 0
    with run_lock(run_dir):
        done = {e.episode_id for e in open_run(run_dir, header, INSPECT_RESUME_KEYS)}
        with EpisodeWriter(run_dir) as writer:
            for sample in log.samples or []:
                where = f"{log_path.name}, sample {sample.id}"
                if sample.error is not None:
                    errored += 1
                    continue
                instruction = _canonical(sample.metadata.get("episode_id", sample.id), where, known)
                if instruction.id in done:
                    continue
                try:
                    plan = check_plan(sample.store.get(_PLAN_KEY, []), where)
                except PlanFormatError as exc:
                    raise ValueError(str(exc)) from None
                trace = execute_plan(backend, get_task(instruction.task_id), plan, max_steps=max_steps)
                if trace.success != _logged_success(sample, where):
                    raise ValueError(
                        f"{where}: the log scores it {'not ' if trace.success else ''}successful, but its "
                        f"{len(plan)} skills {'reach' if trace.success else 'miss'} the goal in the simulator"
                    )
                writer.write(
                    EpisodeRecord.from_trace(instruction, plan, trace, notes={"inspect_sample": str(sample.id)})
                )
                done.add(instruction.id)
                imported += 1
                successes += trace.success
    return ImportSummary(run_dir, imported, errored, successes)
