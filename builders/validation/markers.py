"""The paper's linguistic markers, defined from the literature and computed on spaCy parses.

The paper (appendix "Comparison with Real Dementia Speech") computes part-of-speech and syntactic markers
with a spaCy pipeline and follows Fraser et al. (2016), "Linguistic features identify Alzheimer's disease in
narrative speech", Journal of Alzheimer's Disease 49, 407-422, for the lexical ratios. Each function below
takes a parsed `Doc` (any object with spaCy's token attributes) and says where its definition comes from.
The word lists are in `builders.validation.sources`; none comes from the generator or the verifier.

Words are the tokens that are neither punctuation nor whitespace. spaCy's small English pipeline tags a
sentence-initial filled pause ("Hmm, ...") as a proper noun; filled pauses are never counted as nouns here
(they are counted as discourse markers), which is the one correction made to spaCy's tags.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import Any

from builders.validation.sources import (
    CONNECTIVE_MARKERS,
    EDITING_PHRASES,
    EDITING_WORDS,
    FILLED_PAUSES,
    GENERAL_NOUNS,
    NON_DISCOURSE_INTERJECTIONS,
    PHRASAL_MARKERS,
    PLACEHOLDER_NOUNS,
)

__all__ = [
    "MARKER_LABELS",
    "REPAIR_WINDOW",
    "discourse_marker_count",
    "doc_markers",
    "mtld",
    "parse_depth",
    "repair_count",
    "sentence_texts",
    "words",
]

MARKER_LABELS: dict[str, str] = {
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

REPAIR_WINDOW = 4
"""Editing terms (and a parsed reparandum) at most this many words apart in one sentence are one repair."""

_NOMINAL_ARGUMENTS = frozenset({"dobj", "nsubj", "nsubjpass", "attr", "dative", "oprd"})
_NOUN_POS = frozenset({"NOUN", "PROPN"})


def words(doc: Iterable[Any]) -> list[Any]:
    return [t for t in doc if not t.is_punct and not t.is_space]


def _is_noun(token: Any) -> bool:
    return token.pos_ in _NOUN_POS and token.lower_ not in FILLED_PAUSES


def _is_vague_noun(token: Any) -> bool:
    forms = {token.lower_, token.lemma_.lower()}
    return _is_noun(token) and bool(forms & (GENERAL_NOUNS | PLACEHOLDER_NOUNS))


def mtld(tokens: Sequence[str], threshold: float = 0.72) -> float:
    """MTLD (McCarthy & Jarvis 2010, "MTLD, vocd-D, and HD-D", Behavior Research Methods 42, 381-392).

    Reading the text forward, the type-token ratio of the current factor is updated word by word; when it
    falls to the threshold (0.72, the authors' default) the factor count rises by one and a new factor
    starts. What is left at the end counts as a partial factor, (1 - its TTR) / (1 - 0.72). MTLD is the
    word count over the factor count, averaged over a forward and a backward pass. A text whose words are
    all distinct has no full and no partial factor; it is given one factor (MTLD = its length), the
    convention of the reference implementations. McCarthy & Jarvis advise at least 100 words; the
    instructions are 10-60, so MTLD is dominated by the partial factor, as in the paper's own numbers.
    """

    def one_pass(sequence: Sequence[str]) -> float:
        factors = 0.0
        types: set[str] = set()
        count = 0
        for token in sequence:
            types.add(token)
            count += 1
            if len(types) / count <= threshold:
                factors += 1
                types, count = set(), 0
        if count:
            factors += (1 - len(types) / count) / (1 - threshold)
        return len(sequence) / factors if factors else float(len(sequence))

    lowered = [t.lower() for t in tokens]
    if not lowered:
        return 0.0
    return (one_pass(lowered) + one_pass(lowered[::-1])) / 2


def parse_depth(doc: Any) -> float:
    """Mean over sentences of the dependency tree's height: the most arcs from the root to any word.

    Syntactic depth of a dependency parse (the root at depth 0), as in the height of the parse tree that
    Fraser et al. (2016) use on constituency parses; punctuation is not a word and is left out.
    """
    heights = []
    for sentence in doc.sents:
        tokens = words(sentence)
        if not tokens:
            continue
        best = 0
        for token in tokens:
            depth, node = 0, token
            while node.head.i != node.i:  # spaCy makes a new Token per access: compare indices
                node = node.head
                depth += 1
            best = max(best, depth)
        heights.append(best)
    return sum(heights) / len(heights) if heights else 0.0


def _phrase_matches(tokens: Sequence[Any], phrases: Sequence[tuple[str, ...]]) -> list[tuple[int, int]]:
    """(start, end) token positions in `tokens` of each occurrence of a phrase (longest first, no overlap)."""
    lowered = [t.lower_ for t in tokens]
    taken: set[int] = set()
    spans = []
    for phrase in sorted(phrases, key=len, reverse=True):
        n = len(phrase)
        for start in range(len(lowered) - n + 1):
            if tuple(lowered[start : start + n]) == phrase and not taken & set(range(start, start + n)):
                spans.append((start, start + n))
                taken.update(range(start, start + n))
    return sorted(spans)


def discourse_marker_count(doc: Any) -> int:
    """Discourse markers: the parse's interjections plus a published inventory, counted anywhere.

    A token counts when (1) spaCy parses it as an interjection (POS `INTJ` or the dependency `intj`; the
    UD label `discourse` too, for pipelines that use it), unless it is a politeness marker, greeting, thanks
    or answer particle (Fraser 1996, see `sources`); (2) it is a filled pause; (3) it begins one of the
    phrasal markers of Schiffrin (1987) and Fraser (2009), "you know", "I mean", "by the way", "anyway";
    (4) it is one of the connective markers of Schiffrin (1987) and Fraser (1999) ("well", "so", "and",
    "but", "now", "however", ...) standing in the left periphery of its sentence, with only punctuation and
    other markers before it. A phrase counts once.
    """
    count = 0
    for sentence in doc.sents:
        tokens = list(sentence)
        marked: set[int] = set()
        for start, end in _phrase_matches(tokens, PHRASAL_MARKERS):
            marked.update(range(start, end))
            count += 1
        periphery = True
        for i, token in enumerate(tokens):
            if token.is_punct or token.is_space:
                continue
            if i in marked:
                continue
            lower = token.lower_
            parsed = (token.pos_ == "INTJ" or token.dep_ in {"intj", "discourse"}) and (
                lower not in NON_DISCOURSE_INTERJECTIONS
            )
            if parsed or lower in FILLED_PAUSES or (periphery and lower in CONNECTIVE_MARKERS):
                marked.add(i)
                count += 1
                continue
            periphery = False
    return count


def _editing_positions(sentence: Sequence[Any]) -> list[int]:
    """Token positions where an editing term of self-repair starts (Levelt 1983; see `sources`)."""
    positions = [start for start, _ in _phrase_matches(sentence, EDITING_PHRASES)]
    for i, token in enumerate(sentence):
        lower = token.lower_
        if lower not in EDITING_WORDS:
            continue
        if lower == "no" and not (token.pos_ == "INTJ" or token.dep_ == "intj"):
            continue  # the determiner ("no milk"), not the editing term
        if lower == "rather" and i > 0 and not sentence[i - 1].is_punct:
            continue  # "rather big" is a degree adverb; "or rather" is matched as a phrase
        positions.append(i)
    return sorted(set(positions))


def _reparandum_positions(sentence: Sequence[Any]) -> list[int]:
    """Alterations a parse shows without any editing term (Levelt 1983's instant repairs).

    Two patterns: a noun in apposition to a noun ("put the mug, the cup, in the sink"), and a second
    nominal argument of the same relation on the same head with no coordination ("put the mug, uh, the cup
    in the sink": two direct objects of "put"; coordination would make the second a `conj`).
    """
    start = sentence[0].i
    positions = []
    seen: dict[tuple[int, str], int] = {}
    for token in sentence:
        if token.dep_ == "appos" and _is_noun(token) and _is_noun(token.head):
            positions.append(token.i - start)
        if token.dep_ in _NOMINAL_ARGUMENTS and (token.pos_ in _NOUN_POS or token.pos_ == "PRON"):
            key = (token.head.i, token.dep_)
            if key in seen:
                positions.append(token.i - start)
            seen[key] = token.i
    return sorted(set(positions))


def repair_count(doc: Any) -> int:
    """Self-repairs: clusters of editing terms, plus parsed reparanda that no editing term signals.

    Levelt (1983) describes a repair as reparandum, interruption, optional editing term and alteration.
    Editing terms within `REPAIR_WINDOW` words of each other in one sentence ("no, the basketball, sorry")
    belong to one repair; a parsed reparandum pattern (see `_reparandum_positions`) within the window of an
    editing term is that repair's alteration, farther away it is a repair of its own.
    """
    total = 0
    for sentence in doc.sents:
        tokens = list(sentence)
        # distances are counted in words: "no, the basketball, sorry" is one repair, its commas aside
        word_at = [sum(1 for t in tokens[:i] if not (t.is_punct or t.is_space)) for i in range(len(tokens))]
        editing = [word_at[i] for i in _editing_positions(tokens)]
        clusters: list[list[int]] = []
        for position in editing:
            if clusters and position - clusters[-1][-1] <= REPAIR_WINDOW:
                clusters[-1].append(position)
            else:
                clusters.append([position])
        total += len(clusters)
        for position in (word_at[i] for i in _reparandum_positions(tokens)):
            if not any(abs(position - p) <= REPAIR_WINDOW for p in editing):
                total += 1
    return total


def sentence_texts(doc: Any) -> list[str]:
    """spaCy's sentences of a parsed text, with at least one word each (for sentence-level relevance)."""
    return [s.text.strip() for s in doc.sents if words(s)]


def doc_markers(doc: Any) -> dict[str, float]:
    """Every marker but relevance for one parsed text.

    - pronoun share: pronouns / (nouns + pronouns), Fraser et al. (2016)'s pronoun ratio (spaCy `PRON`,
      possessive and demonstrative pronouns included);
    - noun rate: nouns and proper nouns per word (Fraser et al. 2016);
    - vague-reference share: (pronouns + general and placeholder nouns) / (nouns + pronouns), with Halliday
      & Hasan's (1976) general nouns and Enfield's (2003) placeholders (`sources`);
    - specific-noun rate: nouns other than those vague nouns, per word;
    - discourse markers and repairs: per 100 words (`discourse_marker_count`, `repair_count`);
    - parse depth (`parse_depth`) and MTLD over lowercased words (`mtld`).
    """
    tokens = words(doc)
    n_words = max(len(tokens), 1)
    nouns = [t for t in tokens if _is_noun(t)]
    pronouns = [t for t in tokens if t.pos_ == "PRON"]
    vague = [t for t in nouns if _is_vague_noun(t)]
    nominals = max(len(nouns) + len(pronouns), 1)
    return {
        "repair_rate": 100 * repair_count(doc) / n_words,
        "mtld": mtld([t.text for t in tokens]),
        "vague_reference_share": (len(pronouns) + len(vague)) / nominals,
        "specific_noun_rate": (len(nouns) - len(vague)) / n_words,
        "pronoun_share": len(pronouns) / nominals,
        "noun_rate": len(nouns) / n_words,
        "discourse_markers": 100 * discourse_marker_count(doc) / n_words,
        "parse_depth": parse_depth(doc),
    }
