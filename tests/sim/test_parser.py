"""The skill parser: vocabulary variants parse, anything else is `instruction not supported`."""

from __future__ import annotations

import pytest
from helpers import first_task

from talkdem.sim import FailureKind, parse_skill, run_plan
from talkdem.skills import Skill, SkillVerb, vocabulary


@pytest.mark.parametrize(
    "text",
    ["find an apple", "Find an Apple", "find a apple", "find apple", "  find the apple. ", "FIND AN APPLE"],
)
def test_article_and_case_variants(text: str) -> None:
    assert parse_skill(text) == Skill(SkillVerb.FIND, "Apple")


def test_every_vocabulary_skill_round_trips() -> None:
    assert all(parse_skill(skill.text) == skill for skill in vocabulary())
    assert parse_skill("pick up apple") == Skill(SkillVerb.PICK_UP, "Apple")
    assert parse_skill("Done.") == Skill(SkillVerb.DONE)


@pytest.mark.parametrize(
    "text", ["", "fly to the moon", "slice the mug", "open the apple", "find a unicorn", "done done"]
)
def test_outside_the_vocabulary(text: str) -> None:
    assert parse_skill(text) is None


def test_unsupported_steps_fail_without_ending_the_episode() -> None:
    task = first_task("pick_and_place_simple")
    trace = run_plan(task, ["teleport home", *task.reference_plan])
    assert (trace.steps[0].ok, trace.steps[0].message) == (False, "instruction not supported")
    assert trace.steps[0].failure is FailureKind.NOT_SUPPORTED
    assert trace.success
