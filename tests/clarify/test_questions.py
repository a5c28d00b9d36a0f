"""The question skills, the free-form matcher and the dialogue layout of the SayCan context."""

from __future__ import annotations

import pytest

from talkdem.clarify import QUESTIONS, Slot, is_question, match_question, question_texts
from talkdem.planner.prompt import append_exchange, append_step, build_prompt
from talkdem.skills import skill_texts


def test_one_question_per_slot_none_of_them_an_action_skill() -> None:
    assert set(QUESTIONS) == set(Slot)
    assert not set(question_texts()) & skill_texts()
    assert all(is_question(q) for q in question_texts())
    assert not any(is_question(s) for s in skill_texts())


@pytest.mark.parametrize("slot", list(Slot))
def test_each_fixed_question_matches_its_own_slot(slot: Slot) -> None:
    assert match_question(QUESTIONS[slot]) is slot
    assert match_question("ask: " + QUESTIONS[slot].removeprefix("ask ").upper() + "?") is slot


@pytest.mark.parametrize(
    ("question", "slot"),
    [
        ("ask: where should I put the mug?", Slot.DESTINATION),
        ("ask which lamp should I turn on", Slot.LAMP),
        ("ask: should it be hot or cold?", Slot.STATE),
        ("ask: what should I carry it in?", Slot.CONTAINER),
        ("ask: which one do you mean?", Slot.OBJECT),
        ("ask: what is the task?", Slot.TASK),
        ("ask: how are you today?", None),
        ("ask", None),
    ],
)
def test_free_form_questions_match_by_keyword(question: str, slot: Slot | None) -> None:
    assert match_question(question) is slot


def test_exchanges_are_dialogue_lines_and_the_steps_are_listed_again() -> None:
    context = build_prompt("put it there", ())
    context = append_exchange(context, "ask which object to use", "The apple.")
    assert context.endswith(
        "Human pending instruction: put it there\nRobot: ask which object to use\nPerson: The apple.\nRobot: 1."
    )
    context = append_step(context, "find an apple", 2)
    context = append_exchange(context, "ask  where to put it", "In the\nfridge.")
    assert context.endswith(
        "Robot: 1. find an apple.\nRobot: ask where to put it\nPerson: In the fridge.\nRobot: 1. find an apple, 2."
    )


def test_an_exchange_needs_a_context_ending_in_a_step_number() -> None:
    with pytest.raises(ValueError, match="Robot"):
        append_exchange("no robot line", "ask what the task is", "x")
    with pytest.raises(ValueError, match="number"):
        append_exchange("a\nRobot: 1. find an apple", "ask what the task is", "x")
