"""The shape of an episode record's nested fields: its stored trace (steps, goal report, hazards, analysis, a
clarification run's dialogue, a generative planner's thoughts), its hazard summary, goal counts, notes and
timings.

Every command reads these fields from records on disk (the viewer, the report, score, verify-run, the error
sample), so they are checked once, where a record is read (`EpisodeRecord.from_json`), against what the
writers write (`EpisodeTrace.to_json`, `EpisodeTrace.summary`, `Exchange.to_json`): a hand-edited or damaged
record is one error naming the field, never a TypeError or OverflowError deep inside a command. Numbers must be
finite and in range: a step index or count is a whole number from 0 to `MAX_COUNT` (no episode comes near).

A record may be stored without a trace (plans from elsewhere, hand-made runs; the viewer executes them): a
trace without `steps` holds no simulator facts and is only checked for the fields it does hold.
"""

from __future__ import annotations

import functools
import json
import math
from collections.abc import Callable, Mapping
from typing import Any, NoReturn

__all__ = ["MAX_COUNT", "FieldProblem", "check_nested_fields"]

MAX_COUNT = 2**31 - 1
"""The largest step index or count a record may hold."""


class FieldProblem(ValueError):
    """A nested field without its expected shape; the message names the field (`trace.steps[2].index`)."""


def _shown(value: object) -> str:
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."


def _fail(name: str, expected: str, value: object) -> NoReturn:
    raise FieldProblem(f"field '{name}' must be {expected}, got {_shown(value)}")


def _count(name: str, value: object) -> int:
    if not isinstance(value, int) or isinstance(value, bool) or not 0 <= value <= MAX_COUNT:
        _fail(name, f"a whole number from 0 to {MAX_COUNT}", value)
    return value


def _text(name: str, value: object) -> str:
    if not isinstance(value, str):
        _fail(name, "a string", value)
    return value


def _optional_text(name: str, value: object) -> None:
    if value is not None and not isinstance(value, str):
        _fail(name, "a string or null", value)


def _flag(name: str, value: object) -> None:
    if not isinstance(value, bool):
        _fail(name, "true or false", value)


def _one_of(name: str, value: object, allowed: frozenset[str]) -> None:
    if not isinstance(value, str) or value not in allowed:
        _fail(name, f"one of {', '.join(sorted(allowed))}", value)


def _items(name: str, value: object) -> list[Any]:
    if not isinstance(value, list):
        _fail(name, "a list", value)
    return value


def _text_list(name: str, value: object) -> None:
    for n, item in enumerate(_items(name, value)):
        _text(f"{name}[{n}]", item)


def _object(name: str, value: object, required: tuple[str, ...] = ()) -> dict[str, Any]:
    if not isinstance(value, dict):
        _fail(name, "an object", value)
    for key in required:
        if key not in value:
            raise FieldProblem(f"field '{name}' has no '{key}'")
    return value


@functools.cache
def _values() -> dict[str, frozenset[str]]:
    """The simulator's enumerations (imported when the first record is read, not when the module is)."""
    from talkdem.sim.actions import FailureKind
    from talkdem.sim.hazards import HazardCategory, HazardRule
    from talkdem.sim.trace import EndReason

    return {
        "failure": frozenset(k.value for k in FailureKind),
        "category": frozenset(c.value for c in HazardCategory),
        "rule": frozenset(r.value for r in HazardRule),
        "end_reason": frozenset(e.value for e in EndReason),
    }


_STEP_FIELDS = ("index", "skill", "parsed", "ok", "message", "failure", "object_id", "receptacle_id", "location")


def _step(name: str, value: object) -> None:
    step = _object(name, value, _STEP_FIELDS)
    _count(f"{name}.index", step["index"])
    _text(f"{name}.skill", step["skill"])
    _optional_text(f"{name}.parsed", step["parsed"])
    _flag(f"{name}.ok", step["ok"])
    _text(f"{name}.message", step["message"])
    if step["failure"] is not None:
        _one_of(f"{name}.failure", step["failure"], _values()["failure"])
    for key in ("object_id", "receptacle_id", "location"):
        _optional_text(f"{name}.{key}", step[key])


def _goal(name: str, value: object) -> None:
    goal = _object(name, value, ("task_type", "conditions"))
    _text(f"{name}.task_type", goal["task_type"])
    for n, item in enumerate(_items(f"{name}.conditions", goal["conditions"])):
        where = f"{name}.conditions[{n}]"
        condition = _object(where, item, ("name", "met"))
        _text(f"{where}.name", condition["name"])
        _flag(f"{where}.met", condition["met"])


def _trace_hazard(name: str, value: object) -> None:
    hazard = _object(name, value, ("category", "rule", "step", "detail"))
    _one_of(f"{name}.category", hazard["category"], _values()["category"])
    _one_of(f"{name}.rule", hazard["rule"], _values()["rule"])
    _count(f"{name}.step", hazard["step"])
    _text(f"{name}.detail", hazard["detail"])


_ANALYSIS_TEXT = ("target_object", "target_parent", "target_mrecep", "target_toggle")
_ANALYSIS_LISTS = ("picked_up", "missing_subgoals")


def _analysis(name: str, value: object) -> None:
    analysis = _object(
        name, value, (*_ANALYSIS_TEXT, *_ANALYSIS_LISTS, "placed", "state_reached", "failed_steps", "repeated_steps")
    )
    for key in _ANALYSIS_TEXT:
        _text(f"{name}.{key}", analysis[key])
    for key in _ANALYSIS_LISTS:
        _text_list(f"{name}.{key}", analysis[key])
    for n, pair in enumerate(_items(f"{name}.placed", analysis["placed"])):
        if not (isinstance(pair, list) and len(pair) == 2 and all(isinstance(p, str) for p in pair)):
            _fail(f"{name}.placed[{n}]", "a pair of strings [object, receptacle]", pair)
    reached = _object(f"{name}.state_reached", analysis["state_reached"])
    for key, flag in reached.items():
        _flag(f"{name}.state_reached.{key}", flag)
    for n, pair in enumerate(_items(f"{name}.failed_steps", analysis["failed_steps"])):
        where = f"{name}.failed_steps[{n}]"
        if not (isinstance(pair, list) and len(pair) == 2):
            _fail(where, "a pair [step index, failure kind]", pair)
        _count(f"{where}[0]", pair[0])
        _one_of(f"{where}[1]", pair[1], _values()["failure"])
    _count(f"{name}.repeated_steps", analysis["repeated_steps"])


def _exchange(name: str, value: object) -> None:
    exchange = _object(name, value, ("step", "question", "slot", "answer", "in_pattern"))
    _count(f"{name}.step", exchange["step"])
    for key in ("question", "slot", "answer"):
        _text(f"{name}.{key}", exchange[key])
    _flag(f"{name}.in_pattern", exchange["in_pattern"])


def _each(check: Callable[[str, object], None]) -> Callable[[str, object], None]:
    def every(name: str, value: object) -> None:
        for n, item in enumerate(_items(name, value)):
            check(f"{name}[{n}]", item)

    return every


_TRACE_FIELDS: dict[str, Callable[[str, object], object]] = {
    "task_id": _text,
    "backend": _text,
    "steps": _each(_step),
    "end_reason": lambda name, value: _one_of(name, value, _values()["end_reason"]),
    "goal": _goal,
    "hazards": _each(_trace_hazard),
    "analysis": _analysis,
    "success": _flag,
    "final_state": lambda name, value: None if isinstance(value, dict) else _fail(name, "an object", value),
    "state_hash": _text,
    "dialogue": _each(_exchange),
    "thoughts": _text_list,
}
"""Each field a trace may hold and its check; fields not named here are not read by any command."""

_SIMULATOR_FACTS = ("task_id", "backend", "steps", "end_reason", "goal", "hazards", "analysis")
"""What a stored trace with steps must hold: the facts scoring and the error classifier read."""


def _check_trace(trace: Mapping[str, Any]) -> None:
    if "steps" in trace:
        for key in _SIMULATOR_FACTS:
            if key not in trace:
                raise FieldProblem(f"field 'trace' holds steps but no '{key}' (not a simulator trace)")
    for key, check in _TRACE_FIELDS.items():
        if key in trace:
            check(f"trace.{key}", trace[key])


def _is_finite(value: object) -> bool:
    """A JSON number that is a finite float (an integer of 400 digits is not: it has no float)."""
    if not isinstance(value, int | float) or isinstance(value, bool):
        return False
    try:
        return math.isfinite(value)
    except OverflowError:
        return False


def _top_candidates(name: str, text: str) -> None:
    """`talkdem run --log-top N`: JSON text of each step's best candidates, `[[skill, score], ...]` per step
    (a masked skill scores -Infinity, as Python writes it)."""
    try:
        steps = json.loads(text)
    except (ValueError, RecursionError):  # ValueError: also an integer beyond Python's digit limit
        raise FieldProblem(f"field '{name}' must be JSON text of candidates per step") from None
    for n, step in enumerate(_items(name, steps)):
        for m, pair in enumerate(_items(f"{name}[{n}]", step)):
            ok = isinstance(pair, list) and len(pair) == 2 and isinstance(pair[0], str)
            if not ok or not (_is_finite(pair[1]) or (isinstance(pair[1], float) and math.isinf(pair[1]))):
                _fail(f"{name}[{n}][{m}]", "a pair [skill, score]", pair)


def _summary_hazard(name: str, value: object) -> None:
    hazard = _object(name, value, ("category", "step"))
    _one_of(f"{name}.category", hazard["category"], _values()["category"])
    _count(f"{name}.step", hazard["step"])


def check_nested_fields(data: Mapping[str, Any]) -> None:
    """Check the nested fields of one record's JSON object (its top-level types are checked by the caller);
    `FieldProblem` names the first bad one."""
    _each(_summary_hazard)("hazards", data.get("hazards", []))
    goals = _object("goal_conditions", data.get("goal_conditions", {}))
    if goals:  # `{}`: not recorded
        _object("goal_conditions", goals, ("met", "total"))
        met = _count("goal_conditions.met", goals["met"])
        total = _count("goal_conditions.total", goals["total"])
        if met > total:
            raise FieldProblem(f"field 'goal_conditions.met' ({met}) must not exceed 'goal_conditions.total' ({total})")
    for key, note in _object("notes", data.get("notes", {})).items():
        _text(f"notes.{key}", note)
    if "top_candidates" in data.get("notes", {}):
        _top_candidates("notes.top_candidates", data["notes"]["top_candidates"])
    for key, seconds in _object("timing", data.get("timing", {})).items():
        if not _is_finite(seconds) or seconds < 0:
            _fail(f"timing.{key}", "a finite number of seconds, 0 or more", seconds)
    _check_trace(_object("trace", data.get("trace", {})))
