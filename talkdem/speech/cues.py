"""Closed word lists the structural checks look for: vague references, repairs, empty speech; sentence openers.

The rules generator draws its wording from richer phrase banks, but everything it inserts for a pattern
contains one of these cues, and an LLM generator's output is held to the same lists (the verifier in
`builders/verification` reads them from here). The generator varies its sentences' lead-ins (`openers`), which
the verifier checks as well.
"""

from __future__ import annotations

import re

__all__ = ["EMPTY_SPEECH", "REPAIR", "SENTENCE_BREAK", "VAGUE", "find_all", "openers"]

VAGUE = re.compile(
    r"\b(?:thing|things|thingy|thingamajig|thingamabob|whatsit|whatchamacallit|doodad|gizmo|"
    r"what's it called|what do you call it|what's the word|that one|this one|the one|something|stuff)\b",
    re.IGNORECASE,
)
"""Nonspecific references that stand in for an object name."""

REPAIR = re.compile(
    r"(?:\bno\b(?=[,.!?])|\bno no\b|\bI mean\b|\bI meant\b|\bsorry\b|\bwait\b|\bnot the\b|\bnot that\b|"
    r"\bor rather\b|\boops\b|\bactually\b|\bthat's wrong\b|\bthat's not right\b|\bscratch that\b)",
    re.IGNORECASE,
)
"""Self-correction cues."""

EMPTY_SPEECH = re.compile(
    r"(?:\byou know\b|(?<![\w'])well(?=,)|(?<=,)\s*you see(?=,)|(?<=,)\s*like(?=,)|\bsort of\b|\bkind of\b|"
    r"\band all that\b|"
    r"\band so on\b|\bit is what it is\b|\bthat's how it is\b|\bthat's how it goes\b|\bas they say\b|"
    r"\band what have you\b|\bor whatever\b|\bthis and that\b|\bI don't know\b|\boh dear\b|\blet me see\b|"
    r"\bhow do you say\b|\band everything\b|\bif you follow me\b|\banyhow\b|\bit's all the same\b|"
    r"\bthere we are\b|\bthere you go\b|\bum\b|\buh\b|\bhmm\b|\band so forth\b|\bwhat can you do\b|"
    r"\bit's just one of those\b|\bthe way it is\b|\bhere and there\b|\bone way or another\b)",
    re.IGNORECASE,
)
"""Semantically non-informative speech (fillers, stock phrases, tag-like empty clauses)."""

SENTENCE_BREAK = re.compile(r"[.!?](?=\s|$)")


def find_all(pattern: re.Pattern[str], text: str) -> list[tuple[int, int]]:
    return [(m.start(), m.end()) for m in pattern.finditer(text)]


_OPENER_WORDS = 3


def openers(text: str) -> list[str]:
    """Each sentence's opener: the lowercased words before its first comma, when there are at most three.

    "Mind you, the garden ..." -> "mind you"; "Where was I? Oh yes, in the light." -> "oh yes" (second sentence).
    Sentences without such a lead-in have none.
    """
    out = []
    for sentence in re.split(r"(?<=[.!?])\s+", text.strip()):
        head, comma, _ = sentence.partition(",")
        words = re.findall(r"[\w']+", head.lower())
        if comma and 0 < len(words) <= _OPENER_WORDS:
            out.append(" ".join(words))
    return out
