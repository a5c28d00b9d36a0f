"""Episode records: each step, the goal report, hazards, the final state, and what an error classifier needs."""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import StrEnum
from functools import cached_property
from typing import Any

from talkdem.sim.actions import FailureKind
from talkdem.sim.goals import GoalReport
from talkdem.sim.hazards import Hazard
from talkdem.sim.state import SimState

__all__ = ["EndReason", "EpisodeTrace", "PlanAnalysis", "StepRecord"]


class EndReason(StrEnum):
    """How the episode ended."""

    DONE = "done"
    STEP_LIMIT = "step_limit"
    PLAN_EXHAUSTED = "plan_exhausted"
    """The plan ran out without `done`."""


@dataclass(frozen=True)
class StepRecord:
    """One executed step."""

    index: int
    skill: str
    """The string the planner emitted, verbatim."""
    parsed: str | None
    """Its canonical vocabulary form, or None if it is not a skill."""
    ok: bool
    message: str
    """Empty on success; the simulator's failure message otherwise."""
    failure: FailureKind | None
    object_id: str | None
    """The instance the step acted on (for `put down`, the object put)."""
    receptacle_id: str | None
    """For `put down`: where the object went."""
    location: str | None
    """The agent's location after the step."""


@dataclass(frozen=True)
class PlanAnalysis:
    """Facts an automatic error classifier needs (paper appendix "Error Taxonomy")."""

    target_object: str
    target_parent: str
    target_mrecep: str
    target_toggle: str
    picked_up: tuple[str, ...]
    """Ids the plan successfully picked up, in order (referent resolution: compare with the target)."""
    placed: tuple[tuple[str, str], ...]
    """(object id, receptacle id) of each successful put (location / receptacle errors)."""
    state_reached: dict[str, bool]
    """Whether a target-type object was ever heated, cooled, cleaned, sliced; a target lamp on at the end."""
    missing_subgoals: tuple[str, ...]
    """Reference-plan interactions (canonical skills) that never succeeded in the episode."""
    failed_steps: tuple[tuple[int, FailureKind], ...]
    """Steps whose precondition failed (execution failures), with their kind."""
    repeated_steps: int
    """Successful steps repeating an earlier successful skill (plan organization)."""


@dataclass(frozen=True)
class EpisodeTrace:
    """Everything one episode produced; `to_json()` is the serializable form."""

    task_id: str
    backend: str
    steps: tuple[StepRecord, ...]
    end_reason: EndReason
    goal: GoalReport
    hazards: tuple[Hazard, ...]
    analysis: PlanAnalysis
    state: SimState = field(repr=False, compare=False)
    """The live final state; `final_state` is its serializable form."""

    @cached_property
    def final_state(self) -> dict[str, Any]:
        """The final state in AI2-THOR metadata terms (computed on first use: scoring rarely needs it)."""
        return self.state.to_json()

    @cached_property
    def state_hash(self) -> str:
        """sha256 of the canonical JSON of the final state."""
        return self.state.state_hash()

    @property
    def success(self) -> bool:
        return self.goal.success

    def summary(self) -> dict[str, Any]:
        """The CLI contract (issue section 5)."""
        return {
            "task_id": self.task_id,
            "success": self.success,
            "steps": [{"skill": s.skill, "ok": s.ok, "message": s.message} for s in self.steps],
            "hazards": [{"category": h.category.value, "step": h.step} for h in self.hazards],
            "goal_conditions": {"met": self.goal.met, "total": self.goal.total},
        }

    def to_json(self) -> dict[str, Any]:
        from talkdem.serialization import to_jsonable

        record: dict[str, Any] = {
            name: to_jsonable(getattr(self, name)) for name in self.__dataclass_fields__ if name != "state"
        }
        record.update(success=self.success, final_state=self.final_state, state_hash=self.state_hash)
        return record
