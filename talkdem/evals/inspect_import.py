"""An inspect_ai log of the TALK-Dem task -> a TALK-Dem run directory (`talkdem import-inspect LOG --out RUN`).

Each scored sample becomes one `EpisodeRecord.from_trace`: the skills the agent executed (the sample's
`talkdem_plan` store entry) are stepped through the simulator seam again (deterministic, so this is the
episode the agent played), and an outcome that disagrees with the log's own score is refused, naming the
sample. Every field read from the log is checked first (the task arguments, each sample's episode id, plan
and score): a bad one is one error naming the log, the sample and what was expected, and nothing is written.

The run plans the episodes of the log's task arguments (`conditions`, `limit`: the task's samples, exactly
`talkdem episodes --conditions C --limit N`). Samples that errored are left out and counted, as are samples
inspect never ran (`inspect eval --limit`): the header then says `incomplete`, and `complete` once every
planned episode is there (`talkdem.runs.store.finish_status`, as for `talkdem run`).

A run holds one episode per id, so a log of several epochs (`inspect eval --epochs K`) is imported one
epoch at a time: `epoch` (`--epoch N`) picks it, each into its own run directory, and the header records it
(`config.inspect.epoch`), so a resumed import never mixes two epochs. A several-epoch log without a chosen
epoch is refused, naming the epochs. The header names the inspect model as the model, the solver as the
strategy, and the log by file name (never a machine path: headers are published).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from talkdem.evals.task_args import TaskArgs, check_task_args
from talkdem.instructions import Instruction
from talkdem.plans import Plan, PlanFormatError, check_plan
from talkdem.runs.records import EpisodeRecord, RunHeader
from talkdem.runs.store import EpisodeWriter, finish_status, open_run, run_lock, set_status
from talkdem.schema import parse_instruction_id

__all__ = ["INSPECT_RESUME_KEYS", "ImportSummary", "import_inspect_log"]

INSPECT_RESUME_KEYS = ("model", "planner", "strategy", "dataset_hash", "config.inspect")
_PLAN_KEY = "talkdem_plan"  # the inspect task's store key (talkdem.evals.inspect_task.PLAN_KEY)
_SCORER = "goal_check"


@dataclass(frozen=True)
class ImportSummary:
    run_dir: Path
    imported: int
    errored: int
    """Samples the log holds with an error instead of a score (left out)."""
    successes: int
    status: str = ""
    """The run's status after the import: `complete` or `incomplete`."""
    in_run: int = 0
    """Episodes in the run after the import (a resumed import keeps the earlier ones)."""
    planned: int = 0
    """Episodes the run plans (the selection of the log's task arguments)."""
    epoch: int | None = None
    """The epoch imported, for a log of several epochs."""


@dataclass(frozen=True)
class _Sample:
    """One scored sample, its fields checked."""

    sample_id: str
    instruction: Instruction
    plan: Plan
    logged_success: bool


def _read_log(log_path: Path) -> Any:
    try:
        from inspect_ai.log import read_eval_log
    except ImportError as exc:
        raise ImportError("importing an inspect log needs inspect_ai: pip install 'talkdem[inspect]'") from exc
    if not log_path.is_file():
        raise FileNotFoundError(f"{log_path}: inspect log not found")
    try:
        return read_eval_log(str(log_path))
    except Exception as exc:  # inspect raises its own types (pydantic's for a field of the wrong type)
        raise ValueError(f"{log_path}: not a readable inspect log ({_first_problem(exc)})") from None


def _first_problem(exc: Exception) -> str:
    """One line for what inspect could not read: pydantic names the field and what it expected."""
    errors = getattr(exc, "errors", None)
    if callable(errors):
        try:
            first = errors()[0]
            field = ".".join(str(part) for part in first["loc"])
            return f"field {field}: {first['msg']}, got {first['input']!r}"[:300]
        except (TypeError, KeyError, IndexError):
            pass
    lines = str(exc).strip().splitlines()
    return f"{type(exc).__name__}: {lines[0] if lines else ''}"


def _chosen_epoch(log_path: Path, log: Any, epoch: int | None) -> int | None:
    """The epoch to import: None for a log of one epoch (and `epoch` None or 1), else `epoch`, checked."""
    configured = log.eval.config.epochs
    present = {sample.epoch for sample in log.samples or []}
    count = max([configured if isinstance(configured, int) else 1, *present])
    if count <= 1:
        if epoch not in (None, 1):
            raise ValueError(f"{log_path}: --epoch {epoch}: the log holds one epoch (1)")
        return None
    if epoch is None:
        raise ValueError(
            f"{log_path}: the log holds {count} epochs of each sample (inspect eval --epochs {count}) and a run "
            f"holds one episode per id: import one epoch at a time with --epoch N (1 to {count}), each into "
            "its own --out"
        )
    if not 1 <= epoch <= count:
        raise ValueError(f"{log_path}: --epoch {epoch}: the log holds epochs 1 to {count}")
    return epoch


def _instruction(episode_id: object, where: str, planned: dict[str, Instruction], args: TaskArgs) -> Instruction:
    if not isinstance(episode_id, str):
        raise ValueError(f"{where}: the sample has no TALK-Dem episode id (metadata.episode_id), got {episode_id!r}")
    try:
        task_id, condition = parse_instruction_id(episode_id)
    except ValueError as exc:
        raise ValueError(f"{where}: metadata.episode_id: {exc}") from None
    canonical = condition.instruction_id(task_id)
    if canonical not in planned:
        raise ValueError(
            f"{where}: episode '{episode_id}' is not one the log's task arguments select (conditions="
            f"{args.conditions}, limit={args.limit}); is this a log of the TALK-Dem inspect task?"
        )
    return planned[canonical]


def _logged_success(sample: Any, where: str) -> bool:
    scores = sample.scores or {}
    if _SCORER not in scores:
        raise ValueError(f"{where}: no '{_SCORER}' score (is this a log of the TALK-Dem inspect task?)")
    value = scores[_SCORER].value
    if not isinstance(value, str) or value not in ("C", "I"):
        raise ValueError(f"{where}: the {_SCORER} score must be 'C' or 'I', got {value!r}")
    return value == "C"


def _plan(sample: Any, where: str) -> Plan:
    store = sample.store if isinstance(sample.store, dict) else {}
    if _PLAN_KEY not in store:
        raise ValueError(
            f"{where}: no '{_PLAN_KEY}' in the sample's store (is this a log of the TALK-Dem inspect task?)"
        )
    try:
        return check_plan(store[_PLAN_KEY], f"{where}, store.{_PLAN_KEY}")
    except PlanFormatError as exc:
        raise ValueError(str(exc)) from None


def _checked_samples(
    log_path: Path, samples: Sequence[Any], planned: dict[str, Instruction], args: TaskArgs
) -> tuple[list[_Sample], int]:
    """Every scored sample with its fields checked, and the count of errored ones (left out)."""
    checked: list[_Sample] = []
    seen: dict[str, str] = {}
    errored = 0
    for sample in samples:
        where = f"{log_path}, sample {sample.id}"
        if sample.error is not None:
            errored += 1
            continue
        metadata = sample.metadata if isinstance(sample.metadata, dict) else {}
        instruction = _instruction(metadata.get("episode_id", sample.id), where, planned, args)
        if instruction.id in seen:
            raise ValueError(f"{where}: episode '{instruction.id}' again (first as sample {seen[instruction.id]})")
        seen[instruction.id] = str(sample.id)
        checked.append(_Sample(str(sample.id), instruction, _plan(sample, where), _logged_success(sample, where)))
    return checked, errored


def _records(log_path: Path, samples: Sequence[_Sample], max_steps: int) -> list[EpisodeRecord]:
    """Each sample's plan stepped through the simulator; a log score that disagrees is refused."""
    from talkdem.sim.seam import execute_plan, load_simulator
    from talkdem.tasks import get_task

    backend = load_simulator()
    records = []
    for sample in samples:
        trace = execute_plan(backend, get_task(sample.instruction.task_id), sample.plan, max_steps=max_steps)
        if trace.success != sample.logged_success:
            raise ValueError(
                f"{log_path}, sample {sample.sample_id}: the log scores it {'not ' if trace.success else ''}"
                f"successful, but its {len(sample.plan)} skills {'reach' if trace.success else 'miss'} the goal "
                "in the simulator"
            )
        notes = {"inspect_sample": sample.sample_id}
        records.append(EpisodeRecord.from_trace(sample.instruction, sample.plan, trace, notes=notes))
    return records


def import_inspect_log(log_path: Path, run_dir: Path, *, epoch: int | None = None) -> ImportSummary:
    """Write the log's episodes into `run_dir` (resuming an import of the same log's evaluation and epoch).
    `epoch` picks one epoch of a log of several (refused without it)."""
    from talkdem.schema import parse_conditions

    log = _read_log(log_path)
    spec = log.eval
    task_args = spec.task_args if isinstance(spec.task_args, dict) else {}
    args = check_task_args(task_args, f"{log_path}")
    planned = {instruction.id: instruction for instruction in args.episodes()}
    dataset_size = spec.dataset.samples
    if isinstance(dataset_size, int) and dataset_size != len(planned):
        raise ValueError(
            f"{log_path}: the log's dataset has {dataset_size} samples, but its task arguments (conditions="
            f"{args.conditions}, limit={args.limit}) select {len(planned)} episodes here: a log of another "
            "version of the TALK-Dem task or dataset"
        )
    chosen = _chosen_epoch(log_path, log, epoch)
    samples = [s for s in log.samples or [] if chosen is None or s.epoch == chosen]
    checked, errored = _checked_samples(log_path, samples, planned, args)
    if not checked:  # an import that would do nothing is refused, not an empty run and exit 0
        first_error = next((s.error.message for s in samples if s.error is not None), "")
        why = f" ({errored} errored, the first: {first_error.splitlines()[0][:200]})" if first_error else ""
        raise ValueError(f"{log_path}: no scored sample to import{why}; nothing was written")
    records = _records(log_path, checked, args.max_steps)  # before the run is touched: a refusal writes nothing
    inspect_config: dict[str, Any] = {"task": spec.task, "eval_id": spec.eval_id, "task_args": dict(task_args)}
    if chosen is not None:
        inspect_config["epoch"] = chosen
    header = RunHeader.new(
        model={"backend": "inspect", "name": spec.model, "revision": ""},
        planner="external",
        strategy=spec.solver or "talkdem_agent",
        prompt_version="",
        config={
            "inspect": inspect_config,
            "log": log_path.name,
            "conditions": [str(c) for c in parse_conditions(args.conditions)],
            "limit": args.limit,
            "max_steps": args.max_steps,
            "planned_episodes": len(planned),
        },
    )
    imported = successes = 0
    with run_lock(run_dir):
        done = {e.episode_id for e in open_run(run_dir, header, INSPECT_RESUME_KEYS)}
        try:
            with EpisodeWriter(run_dir) as writer:
                for record in records:
                    if record.episode_id in done:
                        continue
                    writer.write(record)
                    imported += 1
                    successes += record.success
        except BaseException:
            set_status(run_dir, "incomplete")
            raise
        status = finish_status(run_dir, list(planned))
    in_run = len(done | {record.episode_id for record in records})
    return ImportSummary(run_dir, imported, errored, successes, status, in_run, len(planned), chosen)
