"""The simulated person: oracle answers, in-pattern answers by the rules generator, no unasked slot revealed."""

from __future__ import annotations

from collections.abc import Sequence
from functools import cache

import pytest

from talkdem.clarify import DONT_KNOW, SimulatedPerson, Slot, leaked_slots, oracle_answer, slot_type
from talkdem.instructions import Instruction, load_instructions
from talkdem.skills import natural_name
from talkdem.speech import GenerationRequest
from talkdem.tasks import Task, get_task


@cache
def _instructions() -> tuple[Instruction, ...]:
    return tuple(load_instructions())


def _first(task_type: str, pattern: str = "clean", level: int = 0) -> tuple[Instruction, Task]:
    for instruction in _instructions():
        if instruction.task_type == task_type and (instruction.condition.pattern, instruction.condition.level) == (
            pattern,
            level,
        ):
            return instruction, get_task(instruction.task_id)
    raise AssertionError(f"no {task_type} {pattern}:{level} instruction")


def test_oracle_answers_name_the_slot_asked_about() -> None:
    _, task = _first("pick_and_place_with_movable_recep")
    params = task.pddl_params
    assert oracle_answer(task, Slot.OBJECT) == f"The {natural_name(params.object_target)}."
    assert oracle_answer(task, Slot.CONTAINER) == f"In the {natural_name(params.mrecep_target)}."
    assert natural_name(params.parent_target) in oracle_answer(task, Slot.DESTINATION)
    assert oracle_answer(task, Slot.LAMP) == "You don't need a light."
    assert oracle_answer(task, None) == DONT_KNOW
    _, heat = _first("pick_heat_then_place_in_recep")
    assert "Heated." in oracle_answer(heat, Slot.STATE)
    _, lamp = _first("look_at_obj_in_light")
    assert oracle_answer(lamp, Slot.LAMP) == f"The {natural_name(lamp.pddl_params.toggle_target)}."
    assert oracle_answer(lamp, Slot.TASK) == " ".join(lamp.instruction.split())


def test_in_pattern_answers_clean_instructions_like_the_oracle() -> None:
    instruction, task = _first("pick_clean_then_place_in_recep")
    person = SimulatedPerson("in-pattern", instruction, task)
    for slot in Slot:
        assert person.answer(slot) == (oracle_answer(task, slot), False)


def test_in_pattern_answers_are_spoken_under_the_pattern_and_byte_stable() -> None:
    instruction, task = _first("pick_and_place_simple", "empty_speech", 3)
    first = SimulatedPerson("in-pattern", instruction, task)
    again = SimulatedPerson("in-pattern", instruction, task)
    asked = [first.ask("ask which object to use", 0), first.ask("ask which object to use", 1)]
    assert [again.ask("ask which object to use", 0), again.ask("ask which object to use", 1)] == asked
    clear = oracle_answer(task, Slot.OBJECT)
    assert asked[0].in_pattern and asked[0].answer != clear
    assert natural_name(task.pddl_params.object_target) in asked[0].answer.lower()
    assert asked[0].slot == "object" and asked[0].step == 0


def test_a_question_about_nothing_is_not_known() -> None:
    instruction, task = _first("pick_and_place_simple", "intrusion", 2)
    exchange = SimulatedPerson("in-pattern", instruction, task).ask("ask: how are you?", 3)
    assert (exchange.slot, exchange.answer, exchange.in_pattern) == ("", DONT_KNOW, False)


def test_none_is_no_person() -> None:
    instruction, task = _first("pick_and_place_simple")
    with pytest.raises(ValueError, match="oracle"):
        SimulatedPerson("none", instruction, task)


@cache
def _object_names() -> tuple[str, ...]:
    from talkdem.skills import categories
    from talkdem.speech.lexicon import ALIASES

    names = {natural_name(kind) for kind in categories().findable} | {a for v in ALIASES.values() for a in v}
    return tuple(sorted(names, key=len, reverse=True))


def _named(name: str, answer: str) -> bool:
    """`name` as a phrase of `answer`, not inside a longer object name ("toilet" in "toilet paper")."""
    words = f" {' '.join(answer.lower().replace(',', ' ').replace('.', ' ').replace('?', ' ').split())} "
    for longer in _object_names():
        if name in longer and name != longer:
            words = words.replace(f" {longer} ", " _ ")
    return f" {name} " in words


def _other_names(task: Task, slot: Slot) -> set[str]:
    asked = slot_type(task, slot)
    kinds = {task.pddl_params.object_target, task.pddl_params.parent_target}
    kinds |= {task.pddl_params.mrecep_target, task.pddl_params.toggle_target}
    return {natural_name(k) for k in kinds - {asked, ""} if natural_name(k) not in natural_name(asked)}


def test_no_answer_names_an_unasked_slot_over_every_instruction_slot_and_mode() -> None:
    """Every task x pattern x level of the dataset, every slot but the task itself, both modes."""
    leaks, spoken = [], 0
    for instruction in _instructions():
        task = get_task(instruction.task_id)
        for mode in ("oracle", "in-pattern"):
            person = SimulatedPerson(mode, instruction, task)
            for slot in Slot:
                if slot is Slot.TASK:
                    continue
                answer, in_pattern = person.answer(slot)
                spoken += in_pattern
                named = [n for n in _other_names(task, slot) if _named(n, answer)]
                if named or leaked_slots(task, slot, answer):
                    leaks.append((instruction.id, slot.value, answer))
    assert not leaks, leaks[:5]
    assert spoken > len(_instructions())  # most pattern answers really are spoken in pattern


def test_answers_differ_between_episodes_of_one_condition() -> None:
    episodes = [i for i in _instructions() if (i.condition.pattern, i.condition.level) == ("empty_speech", 2)][:12]
    answers = {SimulatedPerson("in-pattern", i, get_task(i.task_id)).answer(Slot.OBJECT)[0] for i in episodes}
    clear = {oracle_answer(get_task(i.task_id), Slot.OBJECT) for i in episodes}
    assert len(answers) > len(clear) // 2 and not answers & clear


class _Echo:
    """A stand-in generator for this test of the person's use of the generator interface."""

    name = "echo-test"
    prompt_version = "1"

    def __init__(self) -> None:
        self.requests: list[GenerationRequest] = []

    def generate(self, requests: Sequence[GenerationRequest]) -> list[str]:
        self.requests += requests
        return [f"{r.clean} ({r.pattern} {r.level})" for r in requests]


def test_in_pattern_answers_come_from_the_generator_named_through_its_interface() -> None:
    from talkdem.speech import register_generator

    echo = _Echo()
    register_generator("echo-test", lambda: echo)
    instruction, task = _first("look_at_obj_in_light", "topic_drift", 3)
    person = SimulatedPerson("in-pattern", instruction, task, generator_name="echo-test")
    exchange = person.ask("ask which light to use", 1)
    lamp = oracle_answer(task, Slot.LAMP)
    assert exchange.answer == f"{lamp} (topic_drift 3)" and exchange.in_pattern
    (request,) = echo.requests
    assert request.task.pddl_params.object_target == task.pddl_params.toggle_target
    assert request.task.pddl_params.toggle_target == task.pddl_params.object_target
