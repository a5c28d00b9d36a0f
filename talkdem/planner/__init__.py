"""The SayCan planner, its prompt, and the mitigation strategies (CARE lives in `care/`)."""

from talkdem.planner.examples import task_type_examples
from talkdem.planner.prompt import Demonstration, build_prompt, format_plan, prompt_version
from talkdem.planner.saycan import PlanResult, SayCanConfig, SayCanPlanner, nearest_skill
from talkdem.planner.strategies import STRATEGIES, PlannerInput, Strategy, load_strategy

__all__ = [
    "STRATEGIES",
    "Demonstration",
    "PlanResult",
    "PlannerInput",
    "SayCanConfig",
    "SayCanPlanner",
    "Strategy",
    "build_prompt",
    "format_plan",
    "load_strategy",
    "nearest_skill",
    "prompt_version",
    "task_type_examples",
]
