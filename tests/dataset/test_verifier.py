"""The verifier on hand-written utterances: each check passes a good one and catches a bad one."""

from __future__ import annotations

import pytest

from builders.verification import CHECKS, verify
from talkdem.tasks import Task, get_task

POTATO = "trial_T20190909_152050_792044"  # "Put a heated potato on the counter." (kitchen; no television, no bed)
LAMP_BOX = "trial_T20190909_042617_850108"  # "Examine a box by the light of a small lamp."
MUG_SPOON = "trial_T20190909_114244_318422"  # "Put a mug with a spoon in it on the table."


@pytest.fixture(scope="module")
def potato() -> Task:
    return get_task(POTATO)


def failed(task_id: str, pattern: str, level: int, text: str) -> list[str]:
    result = verify(get_task(task_id), pattern, level, text)
    assert result["passed"] == (not result["failed_checks"])
    return list(result["failed_checks"])


CLEAN_OK = "Hi there! Could you put a heated potato on the counter? Thanks."


# --- common checks: (check, task, pattern, level, passing utterance, failing utterance) ------------------------------
COMMON_CASES = [
    ("task_verb", POTATO, "clean", 0, CLEAN_OK, "Hi there! A heated potato on the counter, please."),
    ("target_object", POTATO, "clean", 0, CLEAN_OK, "Hi there! Could you put a heated one on the counter?"),
    ("destination", POTATO, "clean", 0, CLEAN_OK, "Hi there! Could you put a heated potato somewhere?"),
    (
        "container",
        MUG_SPOON,
        "clean",
        0,
        "Hello! Put a mug with a spoon in it on the table, please.",
        "Hello! Put a spoon on the table, please.",
    ),
    (
        "toggle_object",
        LAMP_BOX,
        "clean",
        0,
        "Morning. Could you examine a box by the light of a small lamp?",
        "Morning. Could you examine a box for me?",
    ),
    ("state_words", POTATO, "clean", 0, CLEAN_OK, "Hi there! Could you put a potato on the counter? Thanks."),
    (
        "no_added_state",
        POTATO,
        "topic_drift",
        1,
        "Hi! Put a heated potato on the counter, please. The toaster has been there for ages, hasn't it.",
        "Hi! Put a heated potato on the counter, please. The toaster is always so cold, hasn't it.",
    ),
    (
        "scene_objects",
        POTATO,
        "topic_drift",
        1,
        "Hi! Put a heated potato on the counter, please. The toaster has been there for ages.",
        "Hi! Put a heated potato on the counter, please. The television has been there for ages.",
    ),
    ("no_dashes_colons", POTATO, "clean", 0, CLEAN_OK, "Hi there: could you put a heated potato on the counter?"),
    (
        "varied_openers",
        POTATO,
        "referential_imprecision",
        2,
        "Hi, put a heated thingamabob on the counter. Oh, the name. Well, the potato, that's what I mean.",
        "Hi, put a heated thingamabob on the counter. Oh, the name. Oh, the potato, that's what I mean.",
    ),
    (
        "clean_no_pattern",
        POTATO,
        "clean",
        0,
        CLEAN_OK,
        "Hi there! Could you put a heated, you know, potato on the counter?",
    ),
]

# --- pattern checks ---
PATTERN_CASES = [
    (
        "ri_vague_first",
        "referential_imprecision",
        1,
        "Hi! Could you put a heated thingy, the potato, on the counter?",
        "Hi! Could you put a heated potato, the thingy, on the counter?",
    ),
    (
        "ri_immediate_clarification",
        "referential_imprecision",
        1,
        "Hi! Could you put a heated whatsit, I mean the potato, on the counter?",
        "Hi! Could you put a heated whatsit on the counter? The potato, I mean.",
    ),
    (
        "ri_delayed_clarification",
        "referential_imprecision",
        2,
        "Hi! Could you put a heated whatsit on the counter? The potato, I mean.",
        "Hi! Could you put a heated whatsit, the potato, on the counter?",
    ),
    (
        "ri_circumlocution",
        "referential_imprecision",
        3,
        "Hi! Could you put a heated thing, the lumpy brown one that you mash, that one, on the counter? "
        "Oh, what's the word. The potato.",
        "Hi! Could you put a heated thing on the counter? The potato.",
    ),
    (
        "os_competitor_first",
        "object_substitution",
        1,
        "Hi! Could you put a heated tomato, no, the potato on the counter?",
        "Hi! Could you put a heated potato, no, the potato on the counter?",
    ),
    (
        "os_correction",
        "object_substitution",
        1,
        "Hi! Could you put a heated tomato, sorry, the potato on the counter?",
        "Hi! Could you put a heated tomato and the potato on the counter?",
    ),
    (
        "os_immediate_correction",
        "object_substitution",
        1,
        "Hi! Could you put a heated tomato, no, the potato on the counter?",
        "Hi! Could you put a heated tomato on the counter? No, not the tomato. The potato.",
    ),
    (
        "os_delayed_correction",
        "object_substitution",
        2,
        "Hi! Could you put a heated tomato on the counter? No, not the tomato. The potato.",
        "Hi! Could you put a heated tomato, no, the potato on the counter?",
    ),
    (
        "os_repeated_substitution",
        "object_substitution",
        3,
        "Hi! Could you put a heated tomato, the egg, no, on the counter? Wait, not the tomato. The potato.",
        "Hi! Could you put a heated tomato on the counter? No, the potato.",
    ),
    (
        "es_interrupts_request",
        "empty_speech",
        2,
        "Hi! Could you put a heated potato, you know, and all that, on the counter? Well, there we are.",
        "Hi! Could you put a heated potato on the counter? Well, you know, and all that.",
    ),
    (
        "es_amount",
        "empty_speech",
        3,
        "Hi! Could you put, um, a heated potato, you know, and so on, on the counter? Well, what can you do.",
        "Hi! Could you put, um, a heated potato, you know, and so on, on the counter?",
    ),
    (
        "td_drift_after_request",
        "topic_drift",
        2,
        "Hi! Could you put a heated potato on the counter? Is that toaster new? My mother had a pan like it.",
        "Hi! Could you put a heated potato on the counter? Is that toaster new, like my mother's pan?",
    ),
    (
        "td_scene_associations",
        "topic_drift",
        2,
        "Hi! Could you put a heated potato on the counter? Is that toaster new? My mother had a pan like it.",
        "Hi! Could you put a heated potato on the counter? Is that toaster new? My mother had one like it.",
    ),
    (
        "in_interrupts_request",
        "intrusion",
        1,
        "Hi! Could you put a heated potato, oh, is that the doorbell? Anyway, on the counter?",
        "Hi! Could you put a heated potato on the counter? Oh, is that the doorbell? Anyway.",
    ),
    (
        "in_resumed",
        "intrusion",
        2,
        "Hi! Could you put a heated potato, oh, did the postman come? I never know. Anyway, on the counter?",
        "Hi! Could you put a heated potato on the counter, oh, did the postman come? I never know. Anyway.",
    ),
]


def test_every_check_has_a_case() -> None:
    covered = {case[0] for case in COMMON_CASES} | {case[0] for case in PATTERN_CASES}
    assert covered == set(CHECKS)


@pytest.mark.parametrize(
    ("check", "task_id", "pattern", "level", "good", "bad"), COMMON_CASES, ids=[c[0] for c in COMMON_CASES]
)
def test_common_check(check: str, task_id: str, pattern: str, level: int, good: str, bad: str) -> None:
    assert check not in failed(task_id, pattern, level, good)
    assert check in failed(task_id, pattern, level, bad)


@pytest.mark.parametrize(("check", "pattern", "level", "good", "bad"), PATTERN_CASES, ids=[c[0] for c in PATTERN_CASES])
def test_pattern_check(check: str, pattern: str, level: int, good: str, bad: str) -> None:
    assert failed(POTATO, pattern, level, good) == []
    assert check in failed(POTATO, pattern, level, bad)


def test_clean_control_passes_everything() -> None:
    assert failed(POTATO, "clean", 0, CLEAN_OK) == []


def test_seed_wording_missing_from_seed_is_not_required() -> None:
    # "Put the cup on top of the water tank" names no toilet paper (its target): only what the seed names counts
    from talkdem.tasks import load_tasks

    task = next(t for t in load_tasks("benchmark") if t.instruction == "put the cup on top of the water tank")
    assert verify(task, "clean", 0, "Hello! Could you put the cup on top of the water tank?")["passed"]


def test_unknown_pattern_and_level_are_refused(potato: Task) -> None:
    with pytest.raises(ValueError, match="unknown pattern"):
        verify(potato, "mumbling", 1, CLEAN_OK)
    with pytest.raises(ValueError, match="levels"):
        verify(potato, "topic_drift", 4, CLEAN_OK)
