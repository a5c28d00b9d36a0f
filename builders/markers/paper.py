"""The paper's marker table (appendix "Comparison with Real Dementia Speech") and how close ours must come.

Values are the paper's TALK-Dem means for its LLM-generated data (Clean, L1, L2, L3). A cell of ours is
"within tolerance" when it differs from the paper's by at most max(25% of the paper's value, the marker's
absolute floor). The floors only matter near zero (the clean repair rate is 0.00 and the clean discourse-marker
rate 0.04 per 100 words, where 25% would demand exact zeros): half a marker per 100 words is one cue in 200
words, about one in eight clean utterances. The other floors are far below 25% of every paper value in their
rows, so they never decide a cell; they only keep the rule defined for any value.
"""

from __future__ import annotations

__all__ = [
    "DEPARTURES",
    "FLOORS",
    "LEVEL_KEYS",
    "PAPER",
    "RELATIVE_TOLERANCE",
    "follows_papers_column",
    "tolerance",
    "within",
]

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

DEPARTURES: dict[tuple[str, str], str] = {
    ("repair_rate", "object_substitution"): (
        "The paper's Level 2 (4.32) repairs less than its Level 1 (6.10). Level 2 delays the one correction "
        "instead of dropping it, so we keep clean < L1 < L2 < L3: Level 1 sits at the low end of its band and "
        "Level 2 a little above it, outside the paper's band."
    ),
    ("pronoun_share", "referential_imprecision"): (
        "The paper's Level 1 (0.188) falls below its clean control (0.209); a vague noun plus the name adds "
        "nouns, so ours would fall too. We keep the paper's arrow (up) at every step: a third of the Level 1 "
        "clarifications name the speaker or listener (I mean, you know), which puts Level 1 above clean by a "
        "margin that survives another task selection, and a little above the paper's band."
    ),
    ("pronoun_share", "empty_speech"): (
        "The paper's Level 3 (0.413) falls below its Level 2 (0.461). rules-v2 kept rising with the amount of "
        "empty speech; rules-v3's Level 3 adds more whole empty sentences with fewer pronouns, aiming at the "
        "paper's own column (up, up, down) rather than the arrow."
    ),
    ("noun_rate", "empty_speech"): (
        "The paper's Level 3 (0.168) is a little above its Level 2 (0.163); the generator aims at neither shape."
    ),
}
"""Where the paper's own column is not monotonic: what the generator aims at there, and why. How the shipped data
actually moves is computed from markers.json wherever it is shown (`follows_papers_column`)."""


def tolerance(marker: str, paper_value: float) -> float:
    return max(RELATIVE_TOLERANCE * abs(paper_value), FLOORS[marker])


def within(marker: str, paper_value: float, ours: float) -> bool:
    return abs(ours - paper_value) <= tolerance(marker, paper_value)


def follows_papers_column(marker: str, pattern: str, values: dict[str, float]) -> bool:
    """Where the paper's own column turns back (a DEPARTURES entry), whether ours turns with it: every step
    (clean-L1, L1-L2, L2-L3) has the sign of the paper's step. Always False elsewhere, where the arrow rules."""
    if (marker, pattern) not in DEPARTURES:
        return False
    ours = [values[k] for k in LEVEL_KEYS]
    paper = PAPER[(marker, pattern)]
    return all((b - a) * (d - c) > 0 for a, b, c, d in zip(ours, ours[1:], paper, paper[1:], strict=False))
