"""Episode records: each step, the goal report, hazards, the final state, and what an error classifier needs."""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import StrEnum
from functools import cached_property
from typing import Any, Protocol

from talkdem.sim.actions import FailureKind
from talkdem.sim.goals import GoalCondition, GoalReport
from talkdem.sim.hazards import Hazard, HazardCategory, HazardRule
from talkdem.sim.state import SimState

__all__ = ["EndReason", "EpisodeTrace", "PlanAnalysis", "StepRecord", "StoredTrace", "TraceFacts", "TraceFormatError"]


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


class TraceFacts(Protocol):
    """What readers of an episode need (the error classifier, the metric): a live trace or a stored one."""

    @property
    def task_id(self) -> str: ...

    @property
    def steps(self) -> tuple[StepRecord, ...]: ...

    @property
    def end_reason(self) -> EndReason: ...

    @property
    def goal(self) -> GoalReport: ...

    @property
    def hazards(self) -> tuple[Hazard, ...]: ...

    @property
    def analysis(self) -> PlanAnalysis: ...

    @property
    def success(self) -> bool: ...


class TraceFormatError(ValueError):
    """A stored trace without the shape `EpisodeTrace.to_json()` writes."""


@dataclass(frozen=True)
class StoredTrace:
    """An `EpisodeTrace` read back from a run directory: the facts, without the live state (reports read
    these instead of executing the plan again; `talkdem verify-run` is the explicit re-execution)."""

    task_id: str
    backend: str
    steps: tuple[StepRecord, ...]
    end_reason: EndReason
    goal: GoalReport
    hazards: tuple[Hazard, ...]
    analysis: PlanAnalysis
    state_hash: str

    @property
    def success(self) -> bool:
        return self.goal.success

    @classmethod
    def from_json(cls, data: dict[str, Any], where: str = "trace") -> StoredTrace:
        try:
            steps = tuple(
                StepRecord(
                    index=int(s["index"]),
                    skill=str(s["skill"]),
                    parsed=s["parsed"],
                    ok=bool(s["ok"]),
                    message=str(s["message"]),
                    failure=FailureKind(s["failure"]) if s["failure"] is not None else None,
                    object_id=s["object_id"],
                    receptacle_id=s["receptacle_id"],
                    location=s["location"],
                )
                for s in data["steps"]
            )
            goal = data["goal"]
            a = data["analysis"]
            analysis = PlanAnalysis(
                target_object=a["target_object"],
                target_parent=a["target_parent"],
                target_mrecep=a["target_mrecep"],
                target_toggle=a["target_toggle"],
                picked_up=tuple(a["picked_up"]),
                placed=tuple((str(o), str(r)) for o, r in a["placed"]),
                state_reached=dict(a["state_reached"]),
                missing_subgoals=tuple(a["missing_subgoals"]),
                failed_steps=tuple((int(i), FailureKind(k)) for i, k in a["failed_steps"]),
                repeated_steps=int(a["repeated_steps"]),
            )
            return cls(
                task_id=str(data["task_id"]),
                backend=str(data["backend"]),
                steps=steps,
                end_reason=EndReason(data["end_reason"]),
                goal=GoalReport(
                    str(goal["task_type"]),
                    tuple(GoalCondition(str(c["name"]), bool(c["met"])) for c in goal["conditions"]),
                ),
                hazards=tuple(
                    Hazard(HazardCategory(h["category"]), HazardRule(h["rule"]), int(h["step"]), str(h["detail"]))
                    for h in data["hazards"]
                ),
                analysis=analysis,
                state_hash=str(data.get("state_hash", "")),
            )
        except (KeyError, TypeError, ValueError) as exc:
            raise TraceFormatError(
                f"{where}: the stored trace is not a simulator trace ({type(exc).__name__}: {exc})"
            ) from None
