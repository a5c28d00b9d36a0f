"""The stepwise simulator seam: every way from skills to an episode trace goes through here.

A simulator backend starts an episode for a task (`start(task) -> episode`); the episode takes one skill
string at a time (`episode.step(skill) -> StepRecord`) and ends as a trace (`episode.finish() -> EpisodeTrace`).
Backends are registered by name (`SIMULATORS`, like the LLM backends) and imported only when chosen, so the
AI2-THOR adapter costs nothing unless asked for. The step limit lives here once (`DEFAULT_MAX_STEPS`), and
`LimitedSteps` is where every backend's episode refuses a step after `done` or past the limit: a plan executed
in one go (`execute_plan`) and an agent stepping live (the Gymnasium environment, the ReAct planner) cannot
see different episodes.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Protocol

from talkdem.registry import Registry

if TYPE_CHECKING:
    from talkdem.seeds.records import SeedTask
    from talkdem.sim.trace import EndReason, EpisodeTrace, StepRecord

__all__ = [
    "DEFAULT_MAX_STEPS",
    "SIMULATORS",
    "EpisodeOverError",
    "LimitedSteps",
    "SimulatorBackend",
    "SimulatorEpisode",
    "execute_plan",
    "load_simulator",
]

DEFAULT_MAX_STEPS = 30
"""REI-Bench's step limit (LoTa-Bench uses 25); the planner, `talkdem run`, scoring and the backends read it here."""


class EpisodeOverError(ValueError):
    """A step offered to an episode that already ended (at `done` or at the step limit)."""


class SimulatorEpisode(Protocol):
    """One live episode of a backend."""

    max_steps: int

    @property
    def steps(self) -> Sequence[StepRecord]: ...

    @property
    def done(self) -> bool: ...

    @property
    def truncated(self) -> bool: ...

    @property
    def over(self) -> bool: ...

    def step(self, text: str) -> StepRecord: ...

    def finish(self) -> EpisodeTrace: ...


class SimulatorBackend(Protocol):
    """What a registered simulator offers."""

    name: str

    def start(self, task: SeedTask, *, max_steps: int = DEFAULT_MAX_STEPS) -> SimulatorEpisode: ...


class LimitedSteps:
    """The end-of-episode rules every backend's episode shares: `done` ends it, so does `max_steps` steps."""

    task: SeedTask
    max_steps: int
    steps: list[StepRecord]

    @property
    def done(self) -> bool:
        """The last step was `done`."""
        return bool(self.steps) and self.steps[-1].parsed == "done"

    @property
    def truncated(self) -> bool:
        """The step limit was reached without `done`."""
        return not self.done and len(self.steps) >= self.max_steps

    @property
    def over(self) -> bool:
        """No further step belongs to the episode."""
        return self.done or self.truncated

    def _check_open(self) -> None:
        if self.over:
            why = "ended at 'done'" if self.done else f"reached the step limit ({self.max_steps})"
            raise EpisodeOverError(f"task {self.task.task_id}: the episode {why}; no further step is taken")

    def _end_reason(self) -> EndReason:
        from talkdem.sim.trace import EndReason

        return EndReason.DONE if self.done else EndReason.STEP_LIMIT if self.truncated else EndReason.PLAN_EXHAUSTED


SIMULATORS: Registry[SimulatorBackend] = Registry("simulator backend")
SIMULATORS.register("symbolic", "talkdem.sim.executor:SymbolicExecutor", "symbolic (AI2-THOR / LoTa-Bench rules)")
SIMULATORS.register("ai2thor", "talkdem.sim.ai2thor_backend:AI2ThorExecutor", "AI2-THOR (a Unity build)")


def load_simulator(name: str = "symbolic", **options: object) -> SimulatorBackend:
    """The backend registered as `name` (unknown names are refused with the known ones)."""
    return SIMULATORS.create(name, **options)


def execute_plan(
    backend: SimulatorBackend, task: SeedTask, plan: Sequence[str], *, max_steps: int = DEFAULT_MAX_STEPS
) -> EpisodeTrace:
    """Step `plan` through a fresh episode until it ends: steps after `done` or past the limit are not run."""
    episode = backend.start(task, max_steps=max_steps)
    for text in plan:
        if episode.over:
            break
        episode.step(text)
    return episode.finish()
