"""Automatic error classification into the paper's six failure types (appendix "Error Taxonomy").

The paper annotated 270 failures by hand; this classifier applies deterministic rules to the simulator
trace of a failed episode and its task's reference plan. The rules are tried in this order and the
first that holds names the type (each failure gets one primary type, as in the paper):

1. Referent resolution: the plan picks up an object type that the reference plan never picks up and
   never successfully picks up (or slices) the target type; or, in a look-at task, it turns on a lamp
   type other than the target lamp and never the target lamp.
2. Execution failure: the plan's interactions (every skill but `find` and `done`) contain the reference
   plan's interactions in the reference order, yet a step failed in the simulator (object not found or
   not visible, hands full, put/open/toggle/slice failed, or a skill outside the vocabulary).
3. State interpretation: the task requires a state (heated, cooled, cleaned, sliced), the plan names the
   target object in an interaction, and the simulator never reached that state for a target object.
4. Location / receptacle: the plan names the target object, the required state (if any) was reached,
   and the target object (or the movable receptacle of a two-object task) was put down in a receptacle
   type that the reference plan never puts anything in.
5. Subgoal omission: an interaction of the reference plan (e.g. `turn on the desk lamp`, `put down the
   mug`) never occurs in the plan, not even as a failed step.
6. Plan organization: everything else: every required interaction occurs but out of order, repeated,
   undone by a later step, or cut off by the step limit.

Known limits: a wrong *source* location surfaces as an execution failure (the pick up fails), and a
state produced on a non-target object counts as not reached.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum

from talkdem.sim import parse_skill, run_plan
from talkdem.sim.trace import TraceFacts
from talkdem.skills import Skill, SkillVerb
from talkdem.tasks import Task

__all__ = ["ERROR_LABELS", "ErrorClassification", "ErrorType", "classify_error", "required_state"]


class ErrorType(StrEnum):
    """The paper's six failure types, in its table order."""

    REFERENT = "referent_resolution"
    STATE = "state_interpretation"
    LOCATION = "location_receptacle"
    SUBGOAL = "subgoal_omission"
    ORGANIZATION = "plan_organization"
    EXECUTION = "execution_failure"


ERROR_LABELS = {
    ErrorType.REFERENT: "Referent",
    ErrorType.STATE: "State",
    ErrorType.LOCATION: "Location",
    ErrorType.SUBGOAL: "Subgoal",
    ErrorType.ORGANIZATION: "Plan",
    ErrorType.EXECUTION: "Execution",
}
"""Column headings of the paper's error table."""

_STATE_OF_TASK_TYPE = {
    "pick_heat_then_place_in_recep": "heated",
    "pick_cool_then_place_in_recep": "cooled",
    "pick_clean_then_place_in_recep": "cleaned",
}


@dataclass(frozen=True)
class ErrorClassification:
    """The primary failure type and the rule's evidence, in words."""

    type: ErrorType
    reason: str


def required_state(task: Task) -> str | None:
    """The state the goal requires of the target (`PlanAnalysis.state_reached` key), if any."""
    if task.task_type in _STATE_OF_TASK_TYPE:
        return _STATE_OF_TASK_TYPE[task.task_type]
    return "sliced" if task.pddl_params.object_sliced else None


def _skills(texts: tuple[str, ...] | list[str]) -> list[Skill | None]:
    return [parse_skill(text) for text in texts]


def _interactions(skills: list[Skill | None]) -> list[Skill]:
    return [s for s in skills if s is not None and s.verb not in (SkillVerb.FIND, SkillVerb.DONE)]


def _is_subsequence(needle: list[Skill], haystack: list[Skill]) -> bool:
    remaining = iter(haystack)
    return all(any(item == candidate for candidate in remaining) for item in needle)


def _type_of(object_id: str) -> str:
    return object_id.split("|", 1)[0]


_RECEPTACLE_TYPES: dict[tuple[str, tuple[str, ...]], frozenset[str]] = {}


def _reference_receptacle_types(task: Task) -> frozenset[str]:
    """Receptacle types the reference plan puts anything in (sink, microwave, fridge, the goal's parent)."""
    key = (task.task_id, task.reference_plan)
    if key not in _RECEPTACLE_TYPES:
        trace = run_plan(task, task.reference_plan)
        _RECEPTACLE_TYPES[key] = frozenset(_type_of(receptacle) for _, receptacle in trace.analysis.placed)
    return _RECEPTACLE_TYPES[key]


def _names(skill: Skill, object_type: str) -> bool:
    """ALFRED's id-substring matching: `Knife` names `ButterKnife`."""
    return bool(object_type) and object_type in skill.object_type


def classify_error(task: Task, trace: TraceFacts) -> ErrorClassification | None:
    """The primary failure type of a failed episode (None when the episode succeeded)."""
    if trace.success:
        return None
    target = task.pddl_params.object_target
    reference = _interactions(_skills(task.reference_plan))
    emitted_skills = [parse_skill(step.skill) for step in trace.steps]
    emitted = _interactions(emitted_skills)
    ok_interactions = [
        parse_skill(step.skill) for step in trace.steps if step.ok and parse_skill(step.skill) is not None
    ]

    found = _referent(task, reference, emitted, ok_interactions)
    if found:
        return ErrorClassification(ErrorType.REFERENT, found)
    if _is_subsequence(reference, emitted) and trace.analysis.failed_steps:
        index, kind = trace.analysis.failed_steps[0]
        return ErrorClassification(
            ErrorType.EXECUTION,
            f"the plan holds the reference interactions in order, but step {index} failed ({kind.value})",
        )
    target_named = any(_names(s, target) for s in emitted)
    state = required_state(task)
    if state and target_named and not trace.analysis.state_reached.get(state, False):
        return ErrorClassification(ErrorType.STATE, f"the {target} was never {state}")
    if target_named and (not state or trace.analysis.state_reached.get(state, False)):
        allowed = _reference_receptacle_types(task)
        movable = task.pddl_params.mrecep_target
        for object_id, receptacle in trace.analysis.placed:
            moved = _type_of(object_id)
            if (target in moved or (movable and movable in moved)) and _type_of(receptacle) not in allowed:
                return ErrorClassification(
                    ErrorType.LOCATION, f"{moved} put in {_type_of(receptacle)}, a receptacle the task never uses"
                )
    omitted = [s for s in dict.fromkeys(reference) if s not in emitted]
    if omitted:
        return ErrorClassification(ErrorType.SUBGOAL, f"never attempted: {', '.join(s.text for s in omitted)}")
    return ErrorClassification(
        ErrorType.ORGANIZATION,
        f"every reference interaction occurs, but the goal failed (ended: {trace.end_reason.value}, "
        f"{trace.analysis.repeated_steps} repeated steps)",
    )


def _referent(task: Task, reference: list[Skill], emitted: list[Skill], ok: list[Skill | None]) -> str:
    target = task.pddl_params.object_target
    reference_picks = {s.object_type for s in reference if s.verb is SkillVerb.PICK_UP}
    picks = [s.object_type for s in emitted if s.verb is SkillVerb.PICK_UP]
    other_picks = [kind for kind in picks if kind not in reference_picks]
    handled_target = any(
        s is not None and s.verb in (SkillVerb.PICK_UP, SkillVerb.SLICE) and _names(s, target) for s in ok
    )
    if other_picks and not handled_target:
        return f"picked up {other_picks[0]} instead of the target {target}"
    lamp = task.pddl_params.toggle_target
    if lamp:
        turned_on = {s.object_type for s in emitted if s.verb is SkillVerb.TURN_ON}
        if turned_on and lamp not in turned_on:
            return f"turned on {sorted(turned_on)[0]} instead of the target {lamp}"
    return ""
