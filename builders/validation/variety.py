"""Variety of the added wording with object names masked, and the form (sentence count) of each cell.

Counting distinct added sentences overstates variety when the sentences differ only in the object they
name ("The box, I meant the box." / "The mug, I meant the mug."). Here every mention of an AI2-THOR object
type is replaced by `<obj>` before counting. The names come from the rows themselves: the type names of
each task's `scene_objects` and `pddl_params`, split at their capitals ("BaseballBat" -> "baseball bat",
also "baseballbat"), with plural -s/-es, and for a compound type its head noun when it has four letters or
more ("DeskLamp" -> "lamp"; "can" of "GarbageCan" is left alone, it is mostly the verb). Nothing comes from
the generator's lexicon, so its aliases ("keys" for KeyChain) stay unmasked and the figures are, if
anything, on the generous side.
"""

from __future__ import annotations

import re
from collections import Counter
from collections.abc import Iterable, Sequence
from difflib import SequenceMatcher
from typing import Any

__all__ = [
    "EDITED_COVERAGE",
    "MASK",
    "MIN_ADDED",
    "TOP",
    "TOP_SHARE_GOAL",
    "added_sentences",
    "cell_variety",
    "is_edited",
    "masker",
    "object_forms",
    "sentence_count_distribution",
    "split_sentences",
    "type_names",
]

MASK = "<obj>"
TOP = 10
TOP_SHARE_GOAL = 0.40
"""Issue 19's goal: in a cell with at least `MIN_ADDED` added sentences, the `TOP` most frequent (masked)
make up at most this share."""
MIN_ADDED = 30

_HEAD_MIN_LETTERS = 4
_CAMEL = re.compile(r"[A-Z]+(?=[A-Z][a-z])|[A-Z]?[a-z]+|[A-Z]+|\d+")
_SENTENCE_END = re.compile(r"(?<=[.!?])\s+")
_WORD = re.compile(r"<obj>|[\w']+")


def split_sentences(text: str) -> list[str]:
    """Sentences: split after ., ! or ? followed by whitespace (the written form of the utterance)."""
    return [s for s in (part.strip() for part in _SENTENCE_END.split(text.strip())) if s]


def added_sentences(variant: str, clean: str) -> list[str]:
    """Sentences of `variant` that its clean control lacks (each clean sentence cancels one occurrence)."""
    remaining = Counter(split_sentences(clean))
    added = []
    for sentence in split_sentences(variant):
        if remaining[sentence]:
            remaining[sentence] -= 1
        else:
            added.append(sentence)
    return added


EDITED_COVERAGE = 0.6
"""An added sentence that keeps at least this share of a clean sentence's words, in order, is that sentence
edited (a vague word or a filler put into the request), not a sentence the pattern inserted."""


def is_edited(sentence: str, clean: str) -> bool:
    """True when `sentence` is one of `clean`'s sentences with words put in or changed."""
    words = [w.lower() for w in _WORD.findall(sentence)]
    for part in split_sentences(clean):
        reference = [w.lower() for w in _WORD.findall(part)]
        blocks = SequenceMatcher(None, words, reference, autojunk=False).get_matching_blocks()
        if reference and sum(b.size for b in blocks) / len(reference) >= EDITED_COVERAGE:
            return True
    return False


def type_names(rows: Iterable[dict[str, Any]]) -> set[str]:
    """AI2-THOR object types named by the rows (scene objects and task parameters)."""
    names: set[str] = set()
    for row in rows:
        names.update(row.get("scene_objects") or ())
        names.update(v for v in (row.get("pddl_params") or {}).values() if isinstance(v, str) and v)
    return names


def object_forms(type_name: str) -> set[str]:
    """Lowercase surface forms of one type name: spaced and joined words, plurals, the head of a compound."""
    parts = [p.lower() for p in _CAMEL.findall(type_name)]
    if not parts:
        return set()
    bases = {" ".join(parts), "".join(parts)}
    if len(parts) > 1 and len(parts[-1]) >= _HEAD_MIN_LETTERS:
        bases.add(parts[-1])
    return bases | {b + "s" for b in bases} | {b + "es" for b in bases}


def masker(types: Iterable[str]) -> re.Pattern[str]:
    """One case-insensitive pattern for every form of every type, longest first (so "watering can" wins)."""
    forms = sorted({f for t in types for f in object_forms(t)}, key=lambda f: (-len(f), f))
    if not forms:
        return re.compile(r"(?!x)x")  # matches nothing
    alternation = "|".join(re.escape(f).replace(r"\ ", r"\s+") for f in forms)
    return re.compile(rf"\b(?:{alternation})\b", re.IGNORECASE)


def _four_grams(sentence: str) -> list[tuple[str, ...]]:
    tokens = [t.lower() for t in _WORD.findall(sentence)]
    return [tuple(tokens[i : i + 4]) for i in range(len(tokens) - 3)]


def sentence_count_distribution(instructions: Sequence[str]) -> dict[int, int]:
    counts = Counter(len(split_sentences(text)) for text in instructions)
    return dict(sorted(counts.items()))


def cell_variety(pairs: Sequence[tuple[str, str]], mask: re.Pattern[str]) -> dict[str, Any]:
    """Masked variety of one cell from its (variant, clean control) pairs."""
    masked: Counter[str] = Counter()
    inserted: Counter[str] = Counter()
    for variant, clean in pairs:
        for sentence in added_sentences(variant, clean):
            template = mask.sub(MASK, sentence)
            masked[template] += 1
            if not is_edited(sentence, clean):
                inserted[template] += 1
    total = sum(masked.values())
    top = masked.most_common(TOP)
    n_inserted = sum(inserted.values())
    grams: Counter[tuple[str, ...]] = Counter()
    for sentence, count in masked.items():
        for gram in _four_grams(sentence):
            grams[gram] += count
    n_grams = sum(grams.values())
    return {
        "added_sentences": total,
        "templates": len(masked),
        "top10_share": sum(n for _, n in top) / total if total else 0.0,
        "top10": [{"sentence": s, "count": n} for s, n in top],
        # the sentences the pattern put in, without the edited request sentences (unique by their task wording)
        "inserted_sentences": n_inserted,
        "inserted_templates": len(inserted),
        "inserted_top10_share": sum(n for _, n in inserted.most_common(TOP)) / n_inserted if n_inserted else 0.0,
        "four_grams": n_grams,
        "distinct_four_grams": len(grams),
        "distinct_four_gram_share": len(grams) / n_grams if n_grams else 0.0,
        "sentence_counts": sentence_count_distribution([v for v, _ in pairs]),
    }
