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
        "  move the   vase ",
        examples,
        preamble="Robot: AWARE\n",
        demonstrations=[demo],
        demonstrations_intro="INTRO\n",
        interpretation="Hint: Move it.",
    )
    assert prompt.startswith(prompt_text("saycan_header"))
    # Examples as LoTa-Bench labels them; demonstrations and the query as the paper's boxes and REI-Bench do.
    assert "\nHuman: Put a pillow on an ottoman.\nRobot: 1. find a pillow, 2. done.\n" in prompt
    assert "INTRO\nHuman pending instruction: um, the thing, the mug\nPut a mug away.\nRobot: 1. find a mug" in prompt
    # AP's sentence right before the query (REI-Bench), after every example and demonstration.
    assert prompt.endswith(
        "2. done.\nRobot: AWARE\nHuman pending instruction: move the vase\nHint: Move it.\nRobot: 1."
    )
    assert build_prompt("", examples, query_label="Human: ").endswith("done.\nHuman:\nRobot: 1.")
    assert append_step("Robot: 1.", "find a vase", 2) == "Robot: 1. find a vase, 2."
    assert (
        append_step("Robot: 1.", "find a vase", 2, "Cannot find Vase")
        == "Robot: 1. find a vase (this action failed: cannot find vase), 2."
    )
    assert format_plan(["a", "b"]) == "1. a, 2. b."


def test_reference_plan_is_followed_and_succeeds() -> None:
    planner = SayCanPlanner(ScriptedLM(TASK.reference_plan))
    result = planner.plan(TASK, PlannerInput(TASK.instruction))
    assert result.plan == TASK.reference_plan
    assert result.trace.success
    assert len(result.step_scores) == len(result.plan)


class _RecordingLM(ScriptedLM):
    """Keeps every context it was asked to score."""

    def __init__(self, script: list[str]) -> None:
        super().__init__(script)
        self.contexts: list[str] = []

    def loglikelihood(self, requests):  # type: ignore[no-untyped-def]
        self.contexts += [r.context for r in requests]
        return super().loglikelihood(requests)


def test_feedback_policies_mask_and_or_show_the_failure() -> None:
    # `pick up the apple` before any find fails; the script insists on it.
    script = ["pick up the apple", "pick up the apple", "done"]
    results = {}
    for feedback in ("mask", "message", "both", "none"):
        lm = _RecordingLM(script)
        config = SayCanConfig.with_feedback(feedback, max_steps=6)
        assert config.feedback == feedback
        results[feedback] = (SayCanPlanner(lm, config).plan(TASK, PlannerInput("x")).plan, " ".join(lm.contexts))
    for feedback in ("mask", "both"):  # masked: the failed skill is not offered at the next step
        assert results[feedback][0][0] == "pick up the apple" and results[feedback][0][1] != "pick up the apple"
    for feedback in ("message", "none"):
        assert results[feedback][0][:2] == ("pick up the apple", "pick up the apple")
    for feedback in ("message", "both"):  # the simulator's message in the context, REI-Bench's wording
        assert "pick up the apple (this action failed: " in results[feedback][1]
    for feedback in ("mask", "none"):
        assert "this action failed" not in results[feedback][1]
    assert SayCanConfig().feedback == "message"
    with pytest.raises(ValueError, match="feedback must be one of"):
        SayCanConfig.with_feedback("shout")


def test_step_limit_ends_the_episode() -> None:
    result = SayCanPlanner(ScriptedLM(["find an apple"]), SayCanConfig(max_steps=4, failure_message=False)).plan(
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
