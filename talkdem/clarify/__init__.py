"""The clarification track: questions the planner may ask, and a simulated person who answers them."""

from talkdem.clarify.person import (
    CLARIFY_MODES,
    DONT_KNOW,
    PERSON_SEED,
    ClarifyMode,
    Exchange,
    SimulatedPerson,
    leaked_slots,
    oracle_answer,
    slot_type,
)
from talkdem.clarify.questions import QUESTION_MARKER, QUESTIONS, Slot, is_question, match_question, question_texts
from talkdem.clarify.turn import ClarificationTurn

__all__ = [
    "CLARIFY_MODES",
    "DONT_KNOW",
    "PERSON_SEED",
    "QUESTIONS",
    "QUESTION_MARKER",
    "ClarificationTurn",
    "ClarifyMode",
    "Exchange",
    "SimulatedPerson",
    "Slot",
    "is_question",
    "leaked_slots",
    "match_question",
    "oracle_answer",
    "question_texts",
    "slot_type",
]
