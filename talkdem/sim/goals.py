"""ALFRED's goal checks (`env/tasks.py`), evaluated once on the final state, one result per sub-condition.

ALFRED selects objects by substring of the object id (`get_objects_with_name_and_prop`), so `Knife` also
matches `ButterKnife|...` and `Pen` matches `Pencil|...`; this module keeps that behaviour on purpose, so
that success rates match what ALFRED would report.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from talkdem.seeds.records import PddlParams
from talkdem.sim.state import SimState

__all__ = ["REACH_M", "GoalCondition", "GoalReport", "GoalTargets", "check_goals", "goal_targets"]

REACH_M = 1.5
"""AI2-THOR's default `visibilityDistance`: what is this close to the agent is visible and at hand."""


@dataclass(frozen=True)
class GoalCondition:
    """One ALFRED sub-condition and whether it held on the final state."""

    name: str
    met: bool


@dataclass(frozen=True)
class GoalReport:
    """The per-condition results of one task's goal; success means every condition held."""

    task_type: str
    conditions: tuple[GoalCondition, ...]

    @property
    def met(self) -> int:
        return sum(c.met for c in self.conditions)

    @property
    def total(self) -> int:
        return len(self.conditions)

    @property
    def success(self) -> bool:
        return self.met == self.total


@dataclass(frozen=True)
class GoalTargets:
    """The names ALFRED matches against object ids (`XSliced` when the task slices)."""

    object: str
    parent: str
    mrecep: str
    toggle: str
    sliced: bool


def goal_targets(params: PddlParams) -> GoalTargets:
    target = params.object_target
    if params.object_sliced and not target.endswith("Sliced"):
        target += "Sliced"
    return GoalTargets(target, params.parent_target, params.mrecep_target, params.toggle_target, params.object_sliced)


def _named(state: SimState, name: str, prop: str) -> list[str]:
    """ALFRED `get_objects_with_name_and_prop`: present objects whose id contains `name` and have `prop`."""
    if not name:
        return []
    return [o for o in sorted(state.present) if name in o and getattr(state.specs[o], prop)]


def _in_any(state: SimState, objects: list[str], receptacles: list[str]) -> list[str]:
    return [o for o in objects if any(state.contains(r, o) for r in receptacles)]


def _slice_condition(state: SimState, targets: GoalTargets, objects: list[str]) -> list[GoalCondition]:
    if "Sliced" not in targets.object:
        return []
    return [GoalCondition(f"a {targets.object} exists", any("Sliced" in o for o in objects))]


def _simple(state: SimState, t: GoalTargets) -> list[GoalCondition]:
    objects, receptacles = _named(state, t.object, "pickupable"), _named(state, t.parent, "receptacle")
    return [
        *_slice_condition(state, t, objects),
        GoalCondition(f"{t.object} in {t.parent}", bool(_in_any(state, objects, receptacles))),
    ]


def _movable(state: SimState, t: GoalTargets) -> list[GoalCondition]:
    objects, receptacles = _named(state, t.object, "pickupable"), _named(state, t.parent, "receptacle")
    movables = _named(state, t.mrecep, "pickupable")
    stacked = [m for m in movables if _in_any(state, objects, [m]) and _in_any(state, [m], receptacles)]
    return [
        *_slice_condition(state, t, objects),
        GoalCondition(f"{t.object} in {t.mrecep}", bool(_in_any(state, objects, movables))),
        GoalCondition(f"{t.mrecep} in {t.parent}", bool(_in_any(state, movables, receptacles))),
        GoalCondition(f"{t.object} in {t.mrecep} in {t.parent}", bool(stacked)),
    ]


def _changed_then_placed(state_set: Callable[[SimState], set[str]], word: str) -> Callable[..., list[GoalCondition]]:
    def check(state: SimState, t: GoalTargets) -> list[GoalCondition]:
        objects, receptacles = _named(state, t.object, "pickupable"), _named(state, t.parent, "receptacle")
        placed = _in_any(state, objects, receptacles)
        changed = [o for o in objects if o in state_set(state)]
        return [
            *_slice_condition(state, t, objects),
            GoalCondition(f"{t.object} in {t.parent}", bool(placed)),
            GoalCondition(f"{t.object} {word}", bool(changed)),
            GoalCondition(f"the same {t.object} {word} and in {t.parent}", bool(set(placed) & set(changed))),
        ]

    return check


def _look_at(state: SimState, t: GoalTargets) -> list[GoalCondition]:
    objects = _named(state, t.object, "pickupable")
    lamps = _named(state, t.toggle, "toggleable")
    lit = [
        lamp
        for lamp in lamps
        if state.is_toggled.get(lamp, False) and (lamp == state.location or state.distance(lamp) <= REACH_M)
    ]
    return [
        *_slice_condition(state, t, objects),
        GoalCondition(f"holding {t.object}", state.held is not None and state.held in objects),
        GoalCondition(f"{t.toggle} on and visible", bool(lit)),
    ]


_CHECKS: dict[str, Callable[[SimState, GoalTargets], list[GoalCondition]]] = {
    "pick_and_place_simple": _simple,
    "pick_and_place_with_movable_recep": _movable,
    "pick_heat_then_place_in_recep": _changed_then_placed(lambda s: s.heated, "heated"),
    "pick_cool_then_place_in_recep": _changed_then_placed(lambda s: s.cooled, "cooled"),
    "pick_clean_then_place_in_recep": _changed_then_placed(lambda s: s.cleaned, "cleaned"),
    "look_at_obj_in_light": _look_at,
}


def check_goals(task_type: str, params: PddlParams, state: SimState) -> GoalReport:
    """ALFRED's `goal_conditions_met` for the task type, as named per-condition results."""
    if task_type not in _CHECKS:
        raise ValueError(f"unknown ALFRED task type '{task_type}' (known: {', '.join(sorted(_CHECKS))})")
    return GoalReport(task_type, tuple(_CHECKS[task_type](state, goal_targets(params))))
