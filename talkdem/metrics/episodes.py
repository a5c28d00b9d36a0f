"""Scored episodes: what the measurements need of each episode record.

Plans given directly (a mapping, the `evaluate` metric) are executed through the one path from a plan to an
episode record (`talkdem.runs.episode.play_plan`); a run directory is read as stored: its records already
hold the simulator's outcome and trace, so building a report executes nothing (`talkdem verify-run`
re-executes a run explicitly and lists the records that disagree).

Input checking lives here so that every entry point (a mapping of plans, paired predictions/references,
a run directory) fails the same way: a `ScoringInputError` naming the offending ids, never a number
computed from bad input. Unknown skills inside a plan are not input errors: the simulator records them
as failed steps (`instruction not supported`).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from talkdem.plans import as_plan
from talkdem.schema import CLEAN, LEVELS, PATTERN_CONFIGS, Condition, parse_instruction_id
from talkdem.sim import DEFAULT_MAX_STEPS
from talkdem.sim.trace import StoredTrace, TraceFacts, TraceFormatError
from talkdem.skills import SkillVerb

if TYPE_CHECKING:
    from talkdem.runs.records import EpisodeRecord

__all__ = [
    "EpisodeResult",
    "ScoringInputError",
    "check_predictions",
    "execute_plans",
    "instruction_index",
    "pair_predictions",
    "plan_length",
    "results_from_run",
    "split_instruction_id",
]

_SHOWN_IDS = 10


class ScoringInputError(ValueError):
    """Input that cannot be scored; `ids` holds every offending instruction id (or task id)."""

    def __init__(self, problem: str, ids: Iterable[str]) -> None:
        self.ids = tuple(ids)
        shown = ", ".join(self.ids[:_SHOWN_IDS])
        more = f" and {len(self.ids) - _SHOWN_IDS} more" if len(self.ids) > _SHOWN_IDS else ""
        super().__init__(f"{problem}: {shown}{more}" if self.ids else problem)


@dataclass(frozen=True)
class EpisodeResult:
    """One executed instruction, reduced to what the measurements read."""

    instruction_id: str
    task_id: str
    condition: Condition
    """`clean` (level 0) or a pattern at level 1-3."""
    plan: tuple[str, ...]
    success: bool
    hazards: tuple[str, ...]
    """The category (`HazardCategory` value) of each confirmed event, in step order."""
    plan_length: int
    """Steps the simulator executed, failed ones included, not counting the closing `done`."""
    run: str = ""
    """Which run the episode came from (pooled analyses cluster and pair within a run)."""
    trace: TraceFacts | None = field(default=None, repr=False, compare=False)
    """The full trace (the error classifier reads it): live, or as stored in a run; None from summaries."""

    @classmethod
    def from_record(cls, record: EpisodeRecord, run: str = "", trace: TraceFacts | None = None) -> EpisodeResult:
        """The measurements' view of one episode record (its stored trace unless a live one is given)."""
        facts = trace if trace is not None else StoredTrace.from_json(record.trace, f"episode {record.episode_id}")
        return cls(
            instruction_id=record.episode_id,
            task_id=record.task_id,
            condition=record.condition,
            plan=record.plan,
            success=record.success,
            hazards=tuple(str(h["category"]) for h in record.hazards),
            plan_length=plan_length(facts),
            run=run,
            trace=facts,
        )


def plan_length(trace: TraceFacts) -> int:
    """Executed steps without the terminating `done` (the paper's "plan length counts executed steps")."""
    return sum(1 for step in trace.steps if step.parsed != SkillVerb.DONE.value)


def split_instruction_id(instruction_id: str) -> tuple[str, Condition]:
    """`<task>:clean`, `<task>:clean:0` or `<task>:<pattern>:<level>` -> (task id, condition)."""
    try:
        return parse_instruction_id(instruction_id)
    except ValueError:
        raise ScoringInputError(
            "not an instruction id (<task_id>:clean or <task_id>:<pattern>:<level>)", [instruction_id]
        ) from None


def instruction_index() -> dict[str, tuple[str, Condition]]:
    """Every dataset instruction id -> (task id, condition); `<task>:clean` also answers for the clean id."""
    from talkdem.instructions import load_instructions

    index: dict[str, tuple[str, Condition]] = {}
    for instruction in load_instructions():
        entry = (instruction.task_id, instruction.condition)
        index[instruction.id] = entry
        if instruction.condition.pattern == CLEAN:
            index.setdefault(f"{instruction.task_id}:{CLEAN}", entry)
    return index


def _resolve(
    plans: Mapping[str, object], index: Mapping[str, tuple[str, Condition]] | None
) -> list[tuple[str, str, Condition, tuple[str, ...]]]:
    if not plans:
        raise ScoringInputError("no plans to score (the input is empty)", [])
    index = instruction_index() if index is None else index
    unknown = [i for i in plans if not isinstance(i, str) or i not in index]
    if unknown:
        raise ScoringInputError(
            f"unknown instruction ids (not among the {len(index)} dataset ids)", [str(i) for i in unknown]
        )
    bad = [i for i, plan in plans.items() if as_plan(plan) is None]
    if bad:
        raise ScoringInputError("plans must be lists of skill strings; these are not", bad)
    seen: dict[tuple[str, Condition], str] = {}
    clashes: list[str] = []
    resolved = []
    for instruction_id, plan in plans.items():
        task_id, condition = index[instruction_id]
        if (task_id, condition) in seen:  # `<task>:clean` and its long form name the same instruction
            clashes += [seen[(task_id, condition)], instruction_id]
        seen[(task_id, condition)] = instruction_id
        checked = as_plan(plan)
        assert checked is not None  # checked above
        resolved.append((instruction_id, task_id, condition, checked))
    if clashes:
        raise ScoringInputError("duplicate instruction ids (two plans for one instruction)", clashes)
    return resolved


def execute_plans(
    plans: Mapping[str, object],
    *,
    index: Mapping[str, tuple[str, Condition]] | None = None,
    max_steps: int = DEFAULT_MAX_STEPS,
    run: str = "",
) -> list[EpisodeResult]:
    """Check `plans` (instruction id -> list of skills) and execute each for its task (`play_plan`)."""
    from dataclasses import replace

    from talkdem.instructions import load_instructions
    from talkdem.runs.episode import play_plan
    from talkdem.sim.seam import load_simulator

    by_key = {(i.task_id, i.condition): i for i in load_instructions()}
    backend = load_simulator()
    results = []
    for instruction_id, task_id, condition, plan in _resolve(plans, index):
        record, trace = play_plan(by_key[(task_id, condition)], plan, max_steps=max_steps, simulator=backend)
        # The id as the caller wrote it (`<task>:clean` stays short): results are looked up by it.
        results.append(replace(EpisodeResult.from_record(record, run, trace), instruction_id=instruction_id))
    return results


def pair_predictions(predictions: Sequence[object], references: Sequence[object]) -> dict[str, object]:
    """Pair plans with instruction ids by id (the evaluate interface): checks lengths and duplicates."""
    if len(predictions) != len(references):
        raise ScoringInputError(
            f"predictions and references differ in length ({len(predictions)} plans, {len(references)} ids)",
            [str(r) for r in references[len(predictions) :]],
        )
    not_ids = [repr(r) for r in references if not isinstance(r, str)]
    if not_ids:
        raise ScoringInputError("references must be instruction id strings", not_ids)
    counts: dict[str, int] = {}
    for reference in references:
        assert isinstance(reference, str)
        counts[reference] = counts.get(reference, 0) + 1
    duplicated = [i for i, n in counts.items() if n > 1]
    if duplicated:
        raise ScoringInputError("duplicate instruction ids (two plans for one instruction)", duplicated)
    return {str(r): p for r, p in zip(references, predictions, strict=True)}


def check_predictions(predictions: object, references: object) -> None:
    """The evaluate interface's inputs as given, before anything casts them: `predictions` a list of plans
    (each a list of skill strings), `references` a list of id strings of the same length. A
    `ScoringInputError` names the ids whose plans are not lists of strings (a nested step `[["find a box"]]`
    would otherwise be cast to the one skill "['find a box']" and scored as a failed step)."""
    for name, value in (("predictions", predictions), ("references", references)):
        if isinstance(value, str | bytes) or not isinstance(value, Sequence):
            raise ScoringInputError(f"{name} must be a list, got {type(value).__name__}", [])
    assert isinstance(predictions, Sequence) and isinstance(references, Sequence)
    plans = pair_predictions(predictions, references)
    bad = [i for i, plan in plans.items() if as_plan(plan) is None]
    if bad:
        raise ScoringInputError("plans must be lists of skill strings; these are not", bad)


def results_from_run(run_dir: Path, *, run: str = "") -> list[EpisodeResult]:
    """The episodes of a run directory as stored: outcome, hazards and trace are read, nothing is executed
    (`talkdem verify-run` checks them against the simulator)."""
    import warnings

    from talkdem.runs import read_episodes, read_header

    records = read_episodes(run_dir)
    if not records:
        raise ScoringInputError(f"{run_dir}: the run has no episodes", [])
    counts: dict[str, int] = {}
    for record in records:
        counts[record.episode_id] = counts.get(record.episode_id, 0) + 1
    duplicated = [i for i, n in counts.items() if n > 1]
    if duplicated:
        raise ScoringInputError(f"{run_dir}: duplicate episode ids", duplicated)
    results = []
    for record in records:
        condition = record.condition
        known = condition.pattern in PATTERN_CONFIGS and condition.level in LEVELS
        if condition.pattern != CLEAN and not known:
            raise ScoringInputError(f"{run_dir}: episodes with an unknown condition", [record.episode_id])
        try:
            result = EpisodeResult.from_record(record, run)
        except TraceFormatError as exc:
            raise ScoringInputError(f"{run_dir}: {exc}", [record.episode_id]) from None
        if result.success != (result.trace is not None and result.trace.success):
            raise ScoringInputError(
                f"{run_dir}: the stored success flag contradicts the stored trace's goal report", [record.episode_id]
            )
        results.append(result)
    moved = _changed_inputs(read_header(run_dir).inputs)
    if moved:
        warnings.warn(
            f"{run_dir}: input files changed since the run: {', '.join(moved)}; its stored outcomes are what the "
            "run saw (`talkdem verify-run` re-executes them now)",
            stacklevel=2,
        )
    return results


def _changed_inputs(recorded: dict[str, str]) -> list[str]:
    """`NAME (sha256 A... -> B...)` for each input file the run recorded that differs on disk now (runs
    written before inputs were hashed record none)."""
    if not recorded:
        return []
    from talkdem.runs.spec import input_hashes

    now = input_hashes()
    return [
        f"{name} (sha256 {digest[:12]}... -> {now[name][:12]}...)"
        for name, digest in sorted(recorded.items())
        if name in now and now[name] != digest
    ]
