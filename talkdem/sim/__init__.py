"""The household simulator: execute skill plans with AI2-THOR / ALFRED semantics, check goals, flag hazards.

The default backend is symbolic (`SymbolicExecutor`, `run_plan`); `AI2ThorExecutor` drives a real
AI2-THOR build when one is installed. Importing this package never loads torch or transformers.
"""

from talkdem.sim.actions import ACTIONS, FailureKind, StepFailure
from talkdem.sim.ai2thor_backend import AI2ThorExecutor, AI2ThorUnavailableError, ThorAction, translate_skill
from talkdem.sim.executor import DEFAULT_MAX_STEPS, Episode, PlanExecutor, SymbolicExecutor, run_plan
from talkdem.sim.goals import GoalCondition, GoalReport, check_goals
from talkdem.sim.hazards import Hazard, HazardCategory, HazardRule
from talkdem.sim.initial_state import initial_state
from talkdem.sim.parser import parse_skill
from talkdem.sim.state import ObjectSpec, SimState
from talkdem.sim.trace import EndReason, EpisodeTrace, PlanAnalysis, StepRecord

__all__ = [
    "ACTIONS",
    "DEFAULT_MAX_STEPS",
    "AI2ThorExecutor",
    "AI2ThorUnavailableError",
    "EndReason",
    "Episode",
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
    "StepFailure",
    "StepRecord",
    "SymbolicExecutor",
    "ThorAction",
    "check_goals",
    "initial_state",
    "parse_skill",
    "run_plan",
    "translate_skill",
]
