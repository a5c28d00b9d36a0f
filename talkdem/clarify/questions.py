"""The clarification questions: a small fixed set the planner may ask, one per gold slot of the tasks.

The ALFRED task types' gold slots (`PddlParams` and the task type) are: the object (`object_target`, every
type), its destination (`parent_target`, every type but look-at), the movable container (`mrecep_target`,
pick-and-place with a movable receptacle), the lamp (`toggle_target`, look-at), and the object's state
(sliced: `object_sliced`; heated, cooled, cleaned: the task type). One question asks for each, and one for
the whole task. The questions are worded like skills (`ask ...`), so SayCan scores them as continuations
beside the 214 action skills, and a generative or ReAct planner can write them.

Free-form questions (a generative or ReAct planner writes a line starting with `ask`) are matched to a slot
by `match_question`: a question that is exactly one of the fixed questions is that slot; otherwise the first
slot, in `_KEYWORDS`' order, one of whose keywords is a word (or, for phrases, a word sequence) of the
question. The order puts the specific slots (lamp, container, destination, state) before the object and the
task, whose keywords ("which", "what") are generic. No keyword: no slot, and the person answers "I don't
know." A keyword rule rather than an embedding: deterministic, dependency-free, and auditable in one table.
"""

from __future__ import annotations

import re
from enum import StrEnum

__all__ = ["QUESTIONS", "QUESTION_MARKER", "Slot", "is_question", "match_question", "question_texts"]


class Slot(StrEnum):
    """What a question asks for."""

    OBJECT = "object"
    DESTINATION = "destination"
    CONTAINER = "container"
    LAMP = "lamp"
    STATE = "state"
    TASK = "task"


QUESTIONS: dict[Slot, str] = {
    Slot.OBJECT: "ask which object to use",
    Slot.DESTINATION: "ask where to put it",
    Slot.CONTAINER: "ask what to carry it in",
    Slot.LAMP: "ask which light to use",
    Slot.STATE: "ask what state it should be in",
    Slot.TASK: "ask what the task is",
}
"""The question skills, in the order they are offered (after the action skills)."""

QUESTION_MARKER = "ask"
"""A planner's step whose first word is this is a question, not an action."""

_KEYWORDS: tuple[tuple[Slot, tuple[str, ...]], ...] = (
    (Slot.LAMP, ("light", "lamp", "lights", "lamps", "switch on", "turn on")),
    (Slot.CONTAINER, ("carry", "container", "holder", "carry it in", "inside what")),
    (Slot.DESTINATION, ("where", "put", "place", "destination", "leave", "go")),
    (
        Slot.STATE,
        (
            *("state", "condition", "how should", "hot", "cold", "warm", "chill", "heat", "heated", "cool"),
            *("cooled", "clean", "cleaned", "wash", "washed", "slice", "sliced", "cut"),
        ),
    ),
    (Slot.TASK, ("task", "job", "what should i do", "what do you want", "what to do", "do what")),
    (Slot.OBJECT, ("object", "which", "what", "item", "thing", "use", "pick", "take", "get", "bring")),
)

_WORD = re.compile(r"[a-z']+")


def question_texts() -> tuple[str, ...]:
    """The fixed questions, in offering order."""
    return tuple(QUESTIONS.values())


def _words(text: str) -> list[str]:
    return _WORD.findall(text.lower())


def is_question(text: str) -> bool:
    """A step the planner wrote as a question: its first word is `ask` (`ask: where ...` counts too)."""
    words = _words(text)
    return bool(words) and words[0] == QUESTION_MARKER


def match_question(text: str) -> Slot | None:
    """The slot a question asks for (the module's rule), or None when no keyword names one."""
    words = _words(text)
    if words and words[0] == QUESTION_MARKER:
        words = words[1:]
    joined = " ".join(words)
    for slot, question in QUESTIONS.items():
        if joined == " ".join(_words(question)[1:]):
            return slot
    padded = f" {joined} "
    for slot, keywords in _KEYWORDS:
        if any(f" {keyword} " in padded for keyword in keywords):
            return slot
    return None
