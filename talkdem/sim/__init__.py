"""The household simulator: execute skill plans with AI2-THOR / ALFRED semantics, check goals, flag hazards.

The default backend is symbolic (`SymbolicExecutor`, `run_plan`); `AI2ThorExecutor` drives a real
AI2-THOR build when one is installed. Both are registered in `SIMULATORS` and step episodes through one
seam (`talkdem.sim.seam`: `start(task) -> episode`, `episode.step(skill)`, `episode.finish()`).
Importing this package never loads torch or transformers.
"""

from talkdem.sim.actions import ACTIONS, FailureKind, StepFailure
from talkdem.sim.ai2thor_backend import AI2ThorExecutor, AI2ThorUnavailableError, ThorAction, translate_skill
from talkdem.sim.executor import Episode, PlanExecutor, SymbolicExecutor, run_plan
from talkdem.sim.goals import GoalCondition, GoalReport, check_goals
from talkdem.sim.hazards import Hazard, HazardCategory, HazardRule
from talkdem.sim.initial_state import initial_state
from talkdem.sim.parser import parse_skill
from talkdem.sim.seam import (
    DEFAULT_MAX_STEPS,
    SIMULATORS,
    EpisodeOverError,
    SimulatorBackend,
    SimulatorEpisode,
    execute_plan,
    load_simulator,
)
from talkdem.sim.state import ObjectSpec, SimState
from talkdem.sim.trace import EndReason, EpisodeTrace, PlanAnalysis, StepRecord

__all__ = [
    "ACTIONS",
    "DEFAULT_MAX_STEPS",
    "SIMULATORS",
    "AI2ThorExecutor",
    "AI2ThorUnavailableError",
    "EndReason",
    "Episode",
    "EpisodeOverError",
    "EpisodeTrace",
    "FailureKind",
    "GoalCondition",
    "GoalReport",
    "Hazard",
    "HazardCategory",
    "HazardRule",
    "ObjectSpec",
    "PlanAnalysis",
    "PlanExecutor",
    "SimState",
    "SimulatorBackend",
    "SimulatorEpisode",
    "StepFailure",
    "StepRecord",
    "SymbolicExecutor",
    "ThorAction",
    "check_goals",
    "execute_plan",
    "initial_state",
    "load_simulator",
    "parse_skill",
    "run_plan",
    "translate_skill",
]
