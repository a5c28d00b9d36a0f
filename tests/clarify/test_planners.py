"""Every planner asks within its budget, outside the step limit, and shows the exchanges as dialogue."""

from __future__ import annotations

import pytest
from clarify_lm import ClarifyingLM

from talkdem.clarify import SimulatedPerson
from talkdem.instructions import Instruction, load_instructions
from talkdem.planner.react import ReActConfig, ReActPlanner
from talkdem.planner.saycan import SayCanConfig, SayCanPlanner
from talkdem.planner.strategies import PlannerInput
from talkdem.runs.runner import person_for
from talkdem.tasks import Task, get_task

PLANNERS = [
    ("saycan", True),
    ("saycan-generative", False),
    ("react", True),
    ("react", False),
]


def _episode(pattern: str = "object_substitution") -> tuple[Instruction, Task]:
    instruction = next(i for i in load_instructions() if i.condition.pattern == pattern)
    return instruction, get_task(instruction.task_id)


def _plan(
    name: str, scores: bool, script: list[str], mode: str = "oracle", budget: int = 2, max_steps: int = 30
) -> tuple[object, ClarifyingLM, Task]:
    instruction, task = _episode()
    model = ClarifyingLM(script, loglikelihood=scores)
    config: SayCanConfig | ReActConfig
    if name == "react":
        config = ReActConfig(max_steps=max_steps, clarify=mode, clarify_budget=budget)  # type: ignore[arg-type]
        planner: SayCanPlanner | ReActPlanner = ReActPlanner(model, config)
    else:
        generative = "generative" if name == "saycan-generative" else "scoring"
        config = SayCanConfig(max_steps=max_steps, mode=generative, clarify=mode, clarify_budget=budget)  # type: ignore[arg-type]
        planner = SayCanPlanner(model, config)
    result = planner.plan(task, PlannerInput(instruction.text), person=person_for(config, instruction, task))
    return result, model, task


@pytest.mark.parametrize(("name", "scores"), PLANNERS)
def test_questions_are_answered_and_the_actions_alone_are_the_plan(name: str, scores: bool) -> None:
    _, task = _episode()
    plan = list(task.reference_plan)
    # Scoring planners choose among the fixed questions; writing ones may ask in their own words.
    second = "ask where to put it" if scores else "ask: where should it go?"
    script = ["ask which object to use", *plan[:2], second, *plan[2:]]
    result, _, _ = _plan(name, scores, script)
    assert result.plan == task.reference_plan  # type: ignore[attr-defined]
    assert result.trace.success  # type: ignore[attr-defined]
    dialogue = result.dialogue  # type: ignore[attr-defined]
    assert [(e.step, e.slot) for e in dialogue] == [(0, "object"), (2, "destination")]
    assert dialogue[1].question == second


@pytest.mark.parametrize(("name", "scores"), PLANNERS)
def test_the_budget_bounds_questions(name: str, scores: bool) -> None:
    result, _, _ = _plan(name, scores, ["ask which object to use"] * 5, budget=2, max_steps=3)
    assert len(result.dialogue) == 2  # type: ignore[attr-defined]
    assert result.plan  # type: ignore[attr-defined]  # past the budget the planner acts


@pytest.mark.parametrize(("name", "scores"), PLANNERS)
def test_questions_do_not_count_towards_the_step_limit(name: str, scores: bool) -> None:
    _, task = _episode()
    script = ["ask which object to use", "ask what state it should be in", *task.reference_plan]
    result, _, _ = _plan(name, scores, script, budget=2, max_steps=len(task.reference_plan))
    assert len(result.dialogue) == 2  # type: ignore[attr-defined]
    assert result.plan == task.reference_plan  # type: ignore[attr-defined]
    assert result.trace.success  # type: ignore[attr-defined]


def test_saycan_shows_the_exchange_as_robot_and_person_lines() -> None:
    _, task = _episode()
    result, model, _ = _plan("saycan", True, ["ask which object to use", *task.reference_plan], mode="in-pattern")
    answer = result.dialogue[0].answer  # type: ignore[attr-defined]
    assert result.dialogue[0].in_pattern  # type: ignore[attr-defined]
    later = model.contexts[1]
    assert f"\nRobot: ask which object to use\nPerson: {answer}\nRobot: 1." in later
    assert "When a request is unclear" in later


def test_without_clarification_no_question_is_offered() -> None:
    instruction, task = _episode()
    model = ClarifyingLM(["ask which object to use", "done"])
    result = SayCanPlanner(model).plan(task, PlannerInput(instruction.text))
    assert result.dialogue is None
    assert not any(step.startswith("ask") for step in result.plan)
    assert "When a request is unclear" not in model.contexts[0]


def test_a_person_is_needed_exactly_in_clarification_mode() -> None:
    instruction, task = _episode()
    with pytest.raises(ValueError, match="simulated person"):
        SayCanPlanner(ClarifyingLM(["done"]), SayCanConfig(clarify="oracle", clarify_budget=1)).plan(
            task, PlannerInput(instruction.text)
        )
    with pytest.raises(ValueError, match="simulated person"):
        ReActPlanner(ClarifyingLM(["done"])).plan(
            task, PlannerInput(instruction.text), person=SimulatedPerson("oracle", instruction, task)
        )


@pytest.mark.parametrize(
    ("mode", "budget", "message"),
    [("none", 2, "needs clarification"), ("oracle", 0, "at least 1"), ("always", 1, "one of")],
)
def test_bad_clarification_settings(mode: str, budget: int, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        SayCanConfig(clarify=mode, clarify_budget=budget)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=message):
        ReActConfig(clarify=mode, clarify_budget=budget)  # type: ignore[arg-type]
