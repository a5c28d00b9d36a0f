"""Variety of the generated wording: how much the added sentences repeat, repeated openers, article agreement.

Added sentences are the sentences of a variant that its clean control does not have (as a multiset), so a
request sentence with a filler inside counts as added, and the untouched request does not. The goal (issue 14):
in every pattern and level the five most frequent added sentences make up under 10% of all added sentences,
no sentence opener repeats within an utterance, and no indefinite article disagrees with its noun.
"""

from __future__ import annotations

import re
from collections import Counter
from collections.abc import Sequence
from typing import Any

from builders.markers.measures import sentences
from talkdem.speech.cues import openers

__all__ = ["TOP5_GOAL", "added_sentences", "article_errors", "cell_variety", "repeated_opener"]

TOP5_GOAL = 0.10
"""The five most frequent added sentences must stay under this share of all added sentences."""

# "a" before these vowel letters is right (a one, a usual), "an" before these consonant letters too (an hour).
_A_BEFORE_VOWEL = ("one", "once", "use", "usu", "uni", "eu", "ewe")
_AN_BEFORE_CONSONANT = ("hour", "honest", "honou", "heir")
_INDEFINITE = re.compile(r"\b(a|an)\s+([A-Za-z]+)")
# mass and plural nouns with an indefinite article ("a cooled bread", "a keys"); "a loaf of bread" is fine
_MASS = re.compile(
    r"\b(?:a|an)\s+(?:(?!(?:of|with|and|in|on|for)\b)[a-z]+\s+){0,2}(?:bread|toilet paper|soap|keys)\b"
    r"(?!\s+(?:bar|dispenser|bottle|loaf|holder))",
    re.IGNORECASE,
)


def repeated_opener(text: str) -> bool:
    found = openers(text)
    return len(found) != len(set(found))


def added_sentences(variant: str, clean: str) -> list[str]:
    """Sentences of `variant` that `clean` does not have (each clean sentence cancels one occurrence)."""
    remaining = Counter(sentences(clean))
    added = []
    for sentence in sentences(variant):
        if remaining[sentence]:
            remaining[sentence] -= 1
        else:
            added.append(sentence)
    return added


def _article_errors(text: str) -> set[str]:
    """The article-noun phrases of `text` whose indefinite article disagrees with the noun."""
    errors = set()
    for match in _INDEFINITE.finditer(text):
        article, word = match.group(1).lower(), match.group(2).lower()
        vowel = word[0] in "aeiou"
        if (article == "a" and vowel and not word.startswith(_A_BEFORE_VOWEL)) or (
            article == "an" and not vowel and not word.startswith(_AN_BEFORE_CONSONANT)
        ):
            errors.add(match.group(0).lower())
    return errors | {m.group(0).lower() for m in _MASS.finditer(text)}


def article_errors(variant: str, clean: str) -> int:
    """Disagreeing indefinite articles in `variant` other than those its clean control (the seed) already has."""
    return len(_article_errors(variant) - _article_errors(clean))


def cell_variety(rows: Sequence[tuple[str, str]]) -> dict[str, Any]:
    """Variety figures of one pattern-level from (variant, clean control) pairs."""
    counts: Counter[str] = Counter()
    for variant, clean in rows:
        counts.update(added_sentences(variant, clean))
    total = sum(counts.values())
    top = counts.most_common(5)
    return {
        "added_sentences": total,
        "distinct_added_sentences": len(counts),
        "top5_share": sum(n for _, n in top) / total if total else 0.0,
        "top5": [{"sentence": s, "count": n} for s, n in top],
        "repeated_opener_utterances": sum(repeated_opener(v) for v, _ in rows),
        "article_errors": sum(article_errors(v, c) for v, c in rows),
    }
