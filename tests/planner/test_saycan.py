"""The SayCan loop around the model: prompt layout, step handling, feedback policy, scoring modes."""

from __future__ import annotations

import pytest
from scripted_lm import ScriptedLM

from talkdem.planner import PlannerInput, SayCanConfig, SayCanPlanner, build_prompt, format_plan, nearest_skill
from talkdem.planner.prompt import Demonstration, append_step, prompt_text
from talkdem.tasks import TaskSet, load_tasks

TASK = next(t for t in load_tasks(TaskSet.BENCHMARK) if t.task_type == "pick_and_place_simple")


def test_prompt_layout() -> None:
    examples = [Demonstration("Put a pillow on an ottoman.", ("find a pillow", "done"))]
    demo = Demonstration("um, the thing, the mug", ("find a mug", "done"), "Put a mug away.")
    prompt = build_prompt(
        "  move the   vase ", examples, demonstrations=[demo], demonstrations_intro="INTRO\n", interpretation="Move it."
    )
    assert prompt.startswith(prompt_text("saycan_header"))
    assert "Human pending instruction: Put a pillow on an ottoman.\nRobot: 1. find a pillow, 2. done.\n" in prompt
    assert "INTRO\nHuman pending instruction: um, the thing, the mug\nPut a mug away.\nRobot: 1. find a mug" in prompt
    assert prompt.endswith("Human pending instruction: move the vase\nMove it.\nRobot: 1.")
    assert append_step("Robot: 1.", "find a vase", 2) == "Robot: 1. find a vase, 2."
    assert format_plan(["a", "b"]) == "1. a, 2. b."


def test_reference_plan_is_followed_and_succeeds() -> None:
    planner = SayCanPlanner(ScriptedLM(TASK.reference_plan))
    result = planner.plan(TASK, PlannerInput(TASK.instruction))
    assert result.plan == TASK.reference_plan
    assert result.trace.success
    assert len(result.step_scores) == len(result.plan)


def test_failed_skill_is_masked_until_a_step_succeeds() -> None:
    # `pick up the apple` before any find fails; the script insists on it, so masking must move on.
    script = ["pick up the apple", "pick up the apple", "done"]
    masked = SayCanPlanner(ScriptedLM(script), SayCanConfig(max_steps=6)).plan(TASK, PlannerInput("x"))
    assert masked.plan[0] == "pick up the apple" and masked.plan[1] != "pick up the apple"
    unmasked = SayCanPlanner(ScriptedLM(script), SayCanConfig(max_steps=6, mask_failed=False)).plan(
        TASK, PlannerInput("x")
    )
    assert unmasked.plan[:2] == ("pick up the apple", "pick up the apple")


def test_step_limit_ends_the_episode() -> None:
    result = SayCanPlanner(ScriptedLM(["find an apple"]), SayCanConfig(max_steps=4, mask_failed=False)).plan(
        TASK, PlannerInput("x")
    )
    assert len(result.plan) == 4 and "done" not in result.plan
    assert result.trace.end_reason.value in {"step_limit", "plan_exhausted"}


def test_generative_mode_maps_text_to_the_nearest_skill() -> None:
    assert nearest_skill("Pick up the apple.", ["find an apple", "pick up the apple", "done"])[0] == "pick up the apple"
    lm = ScriptedLM(["done"], generated="done.")
    result = SayCanPlanner(lm, SayCanConfig(mode="generative")).plan(TASK, PlannerInput("x"))
    assert result.plan == ("done",) and result.generated == ("done.",)
    assert SayCanConfig(mode="generative").planner_name == "saycan-generative"


def test_scoring_planner_refuses_a_model_without_loglikelihoods() -> None:
    lm = ScriptedLM(["done"])
    lm.supports_loglikelihood = False
    with pytest.raises(ValueError, match="generative"):
        SayCanPlanner(lm)


@pytest.mark.parametrize(
    "script",
    [
        ["pick up the apple", "pick up the apple", "done"],  # failures, masking, done
        ["find an apple"],  # the step limit
        [],  # the reference plan
    ],
)
def test_the_live_episode_is_what_replaying_the_plan_gives(script: list[str]) -> None:
    from talkdem.sim import run_plan

    for task in load_tasks(TaskSet.BENCHMARK)[:12]:
        lm = ScriptedLM(script or list(task.reference_plan))
        config = SayCanConfig(max_steps=8)
        result = SayCanPlanner(lm, config).plan(task, PlannerInput(task.instruction))
        replayed = run_plan(task, result.plan, max_steps=config.max_steps)
        assert result.trace.to_json() == replayed.to_json(), task.task_id
