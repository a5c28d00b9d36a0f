"""Asking in the Gymnasium environment: a question is answered by the simulated person, is not an action and
does not count as a step; past the budget it is a failed step; the dialogue reaches the recorded run and the
report's clarification metrics; in-pattern answers are the same on every run."""

from __future__ import annotations

from pathlib import Path

import pytest

from talkdem.clarify import Slot, oracle_answer
from talkdem.env import EpisodeRecorder, make
from talkdem.instructions import load_instructions
from talkdem.metrics import clarification_scores
from talkdem.runs import read_episodes, read_header
from talkdem.tasks import get_task


def _episode(pattern: str, level: int) -> str:
    return next(i.id for i in load_instructions() if i.condition.pattern == pattern and i.condition.level == level)


def test_a_question_is_answered_and_is_not_a_step(tmp_path: Path) -> None:
    episode_id = _episode("object_substitution", 2)
    env = make(clarify="oracle", clarify_budget=2)
    _, info = env.reset(options={"episode_id": episode_id})
    assert "ask which object to use" in info["questions"] and info["clarify_budget"] == 2
    task = get_task(info["task_id"])
    answer, reward, terminated, truncated, asked = env.step("ask which object to use")
    assert answer == oracle_answer(task, Slot.OBJECT) and (reward, terminated, truncated) == (0.0, False, False)
    assert asked["slot"] == "object" and asked["questions_left"] == 1
    plan = list(task.reference_plan)
    _, _, _, _, first = env.step(plan[0])
    assert first["step"] == 0 and first["ok"], "the question did not use up a simulator step"
    env.step("ask: where does it go?")  # free-form, matched to the destination
    assert env.dialogue[1].slot == "destination" and env.dialogue[1].step == 1
    _, _, _, _, over = env.step("ask which object to use")
    assert not over["ok"] and not over["in_vocabulary"], "past the budget a question is a failed step"
    info = {}
    for skill in plan[1:]:
        *_, info = env.step(skill)
        if "success" in info:
            break
    assert info["success"] and [x.slot for x in info["dialogue"]] == ["object", "destination"]
    instruction = next(i for i in load_instructions() if i.id == episode_id)
    assert env.trace is not None
    with EpisodeRecorder(tmp_path / "run", "asking-agent", "1", clarify="oracle") as recorder:
        recorder.record(instruction, plan, env.trace, dialogue=info["dialogue"])
    (record,) = read_episodes(tmp_path / "run")
    assert [x["answer"] for x in record.trace["dialogue"]] == [x.answer for x in info["dialogue"]]
    assert read_header(tmp_path / "run").config["clarify"] == "oracle"
    scores = clarification_scores([record])
    assert scores is not None and scores.rows["all"].questions_per_episode == 2


def test_without_clarification_a_question_is_a_failed_step() -> None:
    env = make()
    _, info = env.reset(options={"episode_id": _episode("intrusion", 1)})
    assert "questions" not in info
    _, _, _, _, asked = env.step("ask which object to use")
    assert asked["step"] == 0 and not asked["ok"]


def test_in_pattern_answers_are_the_same_on_every_run() -> None:
    episode_id = _episode("referential_imprecision", 3)
    answers = []
    for _ in range(2):
        env = make(clarify="in-pattern")
        env.reset(options={"episode_id": episode_id})
        answers.append([env.step(q)[0] for q in ("ask which object to use", "ask where to put it")])
    assert answers[0] == answers[1] and all(answers[0])


@pytest.mark.parametrize(
    ("options", "message"),
    [({"clarify": "maybe"}, "clarify must be one of"), ({"clarify_budget": -1}, "clarify_budget must be")],
)
def test_bad_clarification_settings_are_named(options: dict[str, object], message: str) -> None:
    with pytest.raises(ValueError, match=message):
        make(**options)
