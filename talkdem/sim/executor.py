"""Run a plan (a list of skill strings) for a task and return its trace: the symbolic backend.

A failed step does not end the episode; `done` does, and so does the step limit (REI-Bench's 30,
`DEFAULT_MAX_STEPS`: the one place the number is written). An `Episode` refuses a step after either, so what a
closed-loop agent sees live is what a stored plan of the same skills scores. Nothing here is random or timed,
so the same task and plan always give the same trace and state hash.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Protocol

from talkdem.seeds.records import SeedTask
from talkdem.sim.actions import ACTIONS, FailureKind, StepFailure, drop_held, remember_destination
from talkdem.sim.goals import GoalReport, check_goals, goal_targets
from talkdem.sim.hazards import HazardMonitor, HazardRule
from talkdem.sim.initial_state import initial_state
from talkdem.sim.parser import canonical_text, parse_skill
from talkdem.sim.seam import DEFAULT_MAX_STEPS, EpisodeOverError, LimitedSteps, execute_plan
from talkdem.sim.state import SimState
from talkdem.sim.trace import EndReason, EpisodeTrace, PlanAnalysis, StepRecord
from talkdem.skills import Skill

__all__ = [
    "DEFAULT_MAX_STEPS",
    "Episode",
    "EpisodeOverError",
    "PlanExecutor",
    "SymbolicExecutor",
    "reference_exemptions",
    "run_plan",
]

NOT_SUPPORTED = "instruction not supported"


class PlanExecutor(Protocol):
    """A backend that runs one whole plan for one task (each backend's `run` is `execute_plan` on its
    `start`; the parity suite replays cases through it)."""

    name: str

    def run(self, task: SeedTask, plan: Sequence[str], *, max_steps: int = DEFAULT_MAX_STEPS) -> EpisodeTrace: ...


_EXEMPTIONS: dict[tuple[str, tuple[str, ...]], frozenset[HazardRule]] = {}


def reference_exemptions(task: SeedTask) -> frozenset[HazardRule]:
    """Hazard rules the task's own reference plan triggers (never flagged for this task)."""
    plan = tuple(getattr(task, "reference_plan", ()))
    key = (task.task_id, plan)
    if key not in _EXEMPTIONS:
        _EXEMPTIONS[key] = frozenset()  # the reference run itself is checked with no exemptions
        trace = _execute(task, plan, DEFAULT_MAX_STEPS, frozenset())
        _EXEMPTIONS[key] = frozenset(h.rule for h in trace.hazards)
    return _EXEMPTIONS[key]


def _step(state: SimState, text: str, index: int) -> tuple[StepRecord, Skill | None]:
    skill = parse_skill(text)
    remember_destination(state, skill)
    if skill is None:
        kind = FailureKind.NOT_SUPPORTED
        return StepRecord(index, text, None, False, NOT_SUPPORTED, kind, None, None, state.location), None
    rule = ACTIONS[skill.verb]
    outcome = rule.precondition(state, skill)
    if isinstance(outcome, StepFailure):
        if outcome.drops_held:
            drop_held(state)
        record = StepRecord(
            index,
            text,
            canonical_text(skill),
            False,
            outcome.message,
            outcome.kind,
            outcome.object_id,
            None,
            state.location,
        )
        return record, skill
    rule.effect(state, outcome)
    record = StepRecord(
        index, text, canonical_text(skill), True, "", None, outcome.object_id, outcome.receptacle_id, state.location
    )
    return record, skill


class Episode(LimitedSteps):
    """One episode stepped by hand (what `run_plan` does in a loop); `state` is live after every step.

    Hazards are judged relative to the task's reference plan (paper appendix "Hazard Detection Rules": a
    sub-rule the reference plan itself triggers is never flagged), however the episode is built: before,
    `Episode(task)` flagged nothing as exempt and `Episode.start(task)` did, so the reference plans of 9
    benchmark tasks (slicing tasks, heating tasks that microwave a knife or a mug) showed hazards one way and
    not the other. `exempt` is for computing those exemptions themselves.
    """

    def __init__(
        self, task: SeedTask, *, max_steps: int = DEFAULT_MAX_STEPS, exempt: frozenset[HazardRule] | None = None
    ) -> None:
        if max_steps < 1:
            raise ValueError(f"max_steps must be at least 1, got {max_steps}")
        self.task = task
        self.max_steps = max_steps
        self.state = initial_state(task)
        self.steps: list[StepRecord] = []
        self._monitor = HazardMonitor(exempt=reference_exemptions(task) if exempt is None else exempt)

    @classmethod
    def start(cls, task: SeedTask, *, max_steps: int = DEFAULT_MAX_STEPS) -> Episode:
        """The simulator seam's entry point (`SimulatorBackend.start`); the same as `Episode(task)`."""
        return cls(task, max_steps=max_steps)

    ended = LimitedSteps.done  # the name the planner used first

    def step(self, text: str) -> StepRecord:
        """Execute one skill string; one outside the vocabulary is a failed step (`instruction not supported`)."""
        self._check_open()
        record, skill = _step(self.state, text, len(self.steps))
        self.steps.append(record)
        self._monitor.observe(record.index, skill, record.ok, record.object_id, self.state)
        return record

    def close(self) -> EpisodeTrace:
        """The trace of the steps taken (`finish` with the end reason they imply)."""
        return self.finish()

    def finish(self, end: EndReason | None = None) -> EpisodeTrace:
        """The trace; `end` defaults to what the steps imply: `done`, the step limit, or a plan that ran out."""
        end = self._end_reason() if end is None else end
        state, steps = self.state, self.steps
        goal = check_goals(self.task.task_type, self.task.pddl_params, state)
        hazards = self._monitor.finish(len(steps) - 1, state) if steps else []
        return EpisodeTrace(
            task_id=self.task.task_id,
            backend=SymbolicExecutor.name,
            steps=tuple(steps),
            end_reason=end,
            goal=goal,
            hazards=tuple(hazards),
            analysis=_analyse(self.task, steps, state, goal),
            state=state,
        )


def _execute(task: SeedTask, plan: Sequence[str], max_steps: int, exempt: frozenset[HazardRule]) -> EpisodeTrace:
    episode = Episode(task, max_steps=max_steps, exempt=exempt)
    for text in plan:
        if episode.over:
            break
        episode.step(text)
    return episode.finish()  # `execute_plan` without the exemptions (which this computes)


def _analyse(task: SeedTask, steps: list[StepRecord], state: SimState, goal: GoalReport) -> PlanAnalysis:
    targets = goal_targets(task.pddl_params)
    ok = [s for s in steps if s.ok]
    done_skills = {s.parsed for s in ok}
    reference = [s for s in getattr(task, "reference_plan", ()) if not s.startswith("find") and s != "done"]
    whole_target = task.pddl_params.object_target

    def reached(ids: set[str]) -> bool:
        return any(whole_target in oid for oid in ids)

    lamp_on = any(on and targets.toggle and targets.toggle in oid for oid, on in state.is_toggled.items())
    seen: set[str | None] = set()
    repeats = 0
    for s in ok:
        repeats += s.parsed in seen and not (s.parsed or "").startswith("find")
        seen.add(s.parsed)
    return PlanAnalysis(
        target_object=targets.object,
        target_parent=targets.parent,
        target_mrecep=targets.mrecep,
        target_toggle=targets.toggle,
        picked_up=tuple(s.object_id for s in ok if s.parsed and s.parsed.startswith("pick up") and s.object_id),
        placed=tuple((s.object_id, s.receptacle_id) for s in ok if s.object_id and s.receptacle_id),
        state_reached={
            "heated": reached(state.heated),
            "cooled": reached(state.cooled),
            "cleaned": reached(state.cleaned),
            "sliced": reached(state.sliced),
            "lamp_on": lamp_on,
            "goal": goal.success,
        },
        missing_subgoals=tuple(dict.fromkeys(s for s in reference if s not in done_skills)),
        failed_steps=tuple((s.index, s.failure) for s in steps if s.failure is not None),
        repeated_steps=repeats,
    )


class SymbolicExecutor:
    """The default backend: AI2-THOR / ALFRED rules on a symbolic state (see docs/simulator.md)."""

    name = "symbolic"

    def start(self, task: SeedTask, *, max_steps: int = DEFAULT_MAX_STEPS) -> Episode:
        return Episode(task, max_steps=max_steps)

    def run(self, task: SeedTask, plan: Sequence[str], *, max_steps: int = DEFAULT_MAX_STEPS) -> EpisodeTrace:
        return execute_plan(self, task, plan, max_steps=max_steps)


def run_plan(task: SeedTask, plan: Sequence[str], *, max_steps: int = DEFAULT_MAX_STEPS) -> EpisodeTrace:
    """Run `plan` for `task` on the symbolic backend."""
    return SymbolicExecutor().run(task, plan, max_steps=max_steps)
