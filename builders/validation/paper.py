"""The paper's marker table (appendix "Comparison with Real Dementia Speech"), as the validation reads it.

A copy of the numbers, not an import of `builders.markers`: that package imports the verifier's cue lists,
which the validation must never load. A test checks that both copies hold the same values.

A cell is within tolerance when it differs from the paper's value by at most max(25% of it, the marker's
floor); the floors only matter near zero (clean repairs 0.00, clean discourse markers 0.04 per 100 words).
A marker moves "in the paper's direction" when clean, L1, L2 and L3 rise (or fall) strictly, step by step.
"""

from __future__ import annotations

import itertools

__all__ = ["DIRECTIONS", "FLOORS", "LEVEL_KEYS", "PAPER", "RELATIVE_TOLERANCE", "moves_as_paper", "within"]

LEVEL_KEYS = ("clean", "1", "2", "3")

PAPER: dict[tuple[str, str], tuple[float, float, float, float]] = {
    ("repair_rate", "object_substitution"): (0.00, 6.10, 4.32, 12.41),
    ("mtld", "object_substitution"): (35.4, 35.1, 20.9, 19.6),
    ("vague_reference_share", "referential_imprecision"): (0.210, 0.355, 0.433, 0.491),
    ("specific_noun_rate", "referential_imprecision"): (0.260, 0.227, 0.201, 0.182),
    ("pronoun_share", "referential_imprecision"): (0.209, 0.188, 0.308, 0.351),
    ("pronoun_share", "empty_speech"): (0.209, 0.370, 0.461, 0.413),
    ("noun_rate", "empty_speech"): (0.260, 0.200, 0.163, 0.168),
    ("discourse_markers", "empty_speech"): (0.04, 8.97, 14.86, 16.98),
    ("parse_depth", "intrusion"): (3.47, 2.77, 2.60, 2.48),
    ("relevance", "topic_drift"): (0.957, 0.666, 0.470, 0.379),
    ("relevance", "intrusion"): (0.957, 0.477, 0.401, 0.391),
}

DIRECTIONS: dict[tuple[str, str], int] = {
    ("repair_rate", "object_substitution"): +1,
    ("mtld", "object_substitution"): -1,
    ("vague_reference_share", "referential_imprecision"): +1,
    ("specific_noun_rate", "referential_imprecision"): -1,
    ("pronoun_share", "referential_imprecision"): +1,
    ("pronoun_share", "empty_speech"): +1,
    ("noun_rate", "empty_speech"): -1,
    ("discourse_markers", "empty_speech"): +1,
    ("parse_depth", "intrusion"): -1,
    ("relevance", "topic_drift"): -1,
    ("relevance", "intrusion"): -1,
}
"""The arrow of the paper's table: the direction of the dementia shift in DementiaBank."""

RELATIVE_TOLERANCE = 0.25

FLOORS: dict[str, float] = {
    "repair_rate": 0.5,
    "discourse_markers": 0.5,
    "mtld": 0.5,
    "vague_reference_share": 0.01,
    "specific_noun_rate": 0.01,
    "pronoun_share": 0.01,
    "noun_rate": 0.01,
    "parse_depth": 0.05,
    "relevance": 0.01,
}


def within(marker: str, paper_value: float, value: float) -> bool:
    return abs(value - paper_value) <= max(RELATIVE_TOLERANCE * abs(paper_value), FLOORS[marker])


def moves_as_paper(sign: int, chain: list[float]) -> bool:
    """True when every step clean -> L1 -> L2 -> L3 moves in direction `sign` (strictly)."""
    return all(sign * (b - a) > 0 for a, b in itertools.pairwise(chain))
