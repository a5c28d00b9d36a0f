"""The form of a `rules-v3` utterance, drawn per utterance from ranges per pattern and level.

`FORMS` is the one place these ranges live: the generator draws from it, the tests read it, and the dataset
card renders it (`definitions_table`) beside the paper's pattern definitions and this project's level
definitions (`talkdem.schema.PATTERNS`). A range `(low, high)` is drawn uniformly per utterance, inclusive;
a share is a probability per utterance.
"""

from __future__ import annotations

import random
from dataclasses import dataclass

from talkdem.schema import PATTERNS

__all__ = ["FORMS", "PAPER_DEFINITIONS", "Form", "chance", "definitions_table", "draw"]


@dataclass(frozen=True)
class Form:
    """What varies in one pattern x level cell, and over which range."""

    ranges: dict[str, tuple[int, int]]
    """Name -> inclusive (low, high), drawn uniformly per utterance."""
    shares: dict[str, float]
    """Name -> probability per utterance."""
    placement: str
    """Where the pattern's material sits, in words."""


FORMS: dict[tuple[str, int], Form] = {
    ("referential_imprecision", 1): Form(
        {"hesitations before the name": (0, 1)},
        {"a short remark on forgetting after the request": 0.3},
        "the vague word replaces the target's first mention; the name follows within six words",
    ),
    ("referential_imprecision", 2): Form(
        {"word-search sentences before the name": (0, 1)},
        {"a tag after the name (of course, dear, ...)": 0.35},
        "the vague word stays in the request; the name comes after the request, before any closing thanks",
    ),
    ("referential_imprecision", 3): Form(
        {"word-search sentences": (1, 2), "vague references in the request": (2, 3)},
        {"a description by look, place or owner": 1.0},
        "vague words and a description stand in the request; the name ends the utterance before any thanks",
    ),
    ("object_substitution", 1): Form(
        {"words between the wrong object and the name": (1, 4)},
        {"a short remark on the slip after the request": 0.2, "the name said twice": 0.6},
        "a wrong in-scene object at the target's first mention, corrected within the phrase",
    ),
    ("object_substitution", 2): Form(
        {"correction sentences": (1, 2)},
        {"the name said twice": 0.9},
        "the wrong object stays through the request; the correction follows it, before any closing thanks",
    ),
    ("object_substitution", 3): Form(
        {"wrong objects": (2, 2), "correction sentences": (1, 2)},
        {"a second slip inside the request": 1.0},
        "two wrong objects in the request; two or more self-corrections settle the target before any thanks",
    ),
    ("empty_speech", 1): Form(
        {"fillers inside the request": (1, 1), "empty sentences": (0, 1)},
        {},
        "one filler at a phrase boundary inside the request (at most three fillers in a row anywhere)",
    ),
    ("empty_speech", 2): Form(
        {"fillers inside the request": (2, 3), "empty sentences": (1, 2)},
        {},
        "fillers at two or three phrase boundaries of the request, then empty sentences",
    ),
    ("empty_speech", 3): Form(
        {"fillers inside the request": (3, 4), "empty sentences": (2, 3)},
        {"an empty sentence before the request": 0.3},
        "fillers between most task phrases, empty sentences around the request",
    ),
    ("topic_drift", 1): Form(
        {"drift sentences": (1, 2), "scene objects": (1, 1)},
        {"the remark ties a task object to a scene object": 0.9},
        "after the complete request (and its thanks): one remark on a scene object, sometimes a short aside "
        "back on the task object",
    ),
    ("topic_drift", 2): Form(
        {"drift sentences": (2, 3), "scene objects": (2, 2)},
        {"the remark ties a task object to a scene object": 0.8},
        "after the request: a remark on a scene object, then a memory of the speaker's own",
    ),
    ("topic_drift", 3): Form(
        {"drift sentences": (4, 5), "scene objects": (3, 4)},
        {"the remark ties a task object to a scene object": 0.7},
        "after the request: a remark, two memories, then the speaker's life far from the task",
    ),
    ("intrusion", 1): Form(
        {"intrusion sentences": (1, 1)},
        {"the intrusion is cut in with a comma (else an ellipsis, a sentence more)": 0.6},
        "at a phrase boundary drawn at random inside the request; the request resumes after a lead-in",
    ),
    ("intrusion", 2): Form(
        {"intrusion sentences": (2, 2)},
        {"the intrusion is cut in with a comma (else an ellipsis, a sentence more)": 0.5},
        "at a phrase boundary drawn at random inside the request; the request resumes after a lead-in",
    ),
    ("intrusion", 3): Form(
        {"fragments in the first intrusion": (2, 3), "sentences in the second intrusion": (1, 1)},
        {},
        "a fragmented intrusion at a random boundary, a restatement of the request so far, a second thought",
    ),
}
"""(pattern, level) -> the ranges each utterance's form is drawn from."""

PAPER_DEFINITIONS: dict[str, str] = {
    "referential_imprecision": "The intended object is initially referred to using a vague or nonspecific "
    "expression, with its identity clarified later or conveyed through circumlocution.",
    "object_substitution": "The intended object is initially replaced by an incorrect but contextually plausible "
    "object, with the object selection revised later in the utterance.",
    "empty_speech": "Task-relevant information is interrupted by semantically non-informative speech, causing "
    "the instruction to become more dispersed across the utterance.",
    "topic_drift": "The instruction is followed by off-task associations that progressively move away from the "
    "original task topic and introduce additional scene-related content.",
    "intrusion": "The task instruction is interrupted by an off-task thought before the request is complete, "
    "with the remaining task information resumed afterward.",
}
"""The paper's pattern definitions (section "TALK-Dem Benchmark"); it gives no per-level definition except its
Referential Imprecision Level 1 prompt, so the level definitions are this project's."""


def draw(rng: random.Random, pattern: str, level: int, name: str) -> int:
    low, high = FORMS[(pattern, level)].ranges[name]
    return rng.randint(low, high)


def chance(rng: random.Random, pattern: str, level: int, name: str) -> bool:
    return rng.random() < FORMS[(pattern, level)].shares[name]


def _cell(text: str) -> str:
    return text.replace("|", "\\|")


def definitions_table() -> str:
    """Markdown: the paper's definition beside this project's level definitions and the drawn form ranges."""
    rows = [
        "| Pattern | The paper's definition | Level | This project's definition | Form drawn per utterance |",
        "| --- | --- | ---: | --- | --- |",
    ]
    for config, pattern in PATTERNS.items():
        for level, meaning in pattern.levels.items():
            form = FORMS[(config, level)]
            ranges = [f"{name}: {lo}" if lo == hi else f"{name}: {lo}-{hi}" for name, (lo, hi) in form.ranges.items()]
            shares = [f"{name}: {round(100 * p)}%" for name, p in form.shares.items()]
            drawn = "; ".join([*ranges, *shares, f"placement: {form.placement}"])
            paper = PAPER_DEFINITIONS[config] if level == 1 else "(same)"
            rows.append(f"| {pattern.abbreviation} | {_cell(paper)} | {level} | {_cell(meaning)} | {_cell(drawn)} |")
    return "\n".join(rows)
