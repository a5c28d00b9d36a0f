"""The task-relevant wording of a seed instruction: what every generated utterance must keep.

Paper, appendix "Benchmark Construction Prompts": the conversational rewrite keeps every task-relevant word
of the seed (object names, action words, destinations, containers, object-state expressions). This module
finds those words in the seed with the object-space lexicon, so that the generator knows what to leave
alone and the verifier knows what to look for.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from talkdem.speech.lexicon import STATE_WORDS, TASK_VERBS, Mention, mentions_of, word_spans
from talkdem.tasks import Task

__all__ = [
    "TaskTerms",
    "noun_phrase",
    "request_body",
    "request_span",
    "span_of",
    "state_kind",
    "task_terms",
    "term_positions",
    "verb_lemma",
]


_VERB_FORMS = {form: lemma for lemma, forms in TASK_VERBS.items() for form in forms}
_STATE_FORMS = {word: kind for kind, words in STATE_WORDS.items() for word in words}
_LEADING = re.compile(r"^(?:to|robot should|the robot should|you should)\s+", re.IGNORECASE)
_DETERMINERS = {"a", "an", "the", "some", "this", "that", "my", "your", "one"}


def verb_lemma(word: str) -> str | None:
    return _VERB_FORMS.get(word.lower())


@dataclass(frozen=True)
class TaskTerms:
    """The task-relevant wording of one seed and the types behind it."""

    seed: str
    role_types: dict[str, str]
    """Role -> object type, for the roles the task has (`toggle` only for look-at tasks)."""
    seed_roles: tuple[str, ...]
    """The roles the seed instruction names (only these are required: ALFRED annotators sometimes omit one)."""
    verbs: tuple[str, ...]
    """Task verb lemmas in the seed, in order, without repeats."""
    state_words: tuple[str, ...]
    """State expressions in the seed (lowercase, in order, without repeats)."""
    state_kinds: frozenset[str]
    """Which state kinds (heat, cool, clean, slice) the seed expresses."""
    seed_words: frozenset[str]

    @property
    def task_types(self) -> frozenset[str]:
        return frozenset(self.role_types.values())


def task_terms(task: Task) -> TaskTerms:
    key = (task.task_id, task.instruction, task.pddl_params)
    if key not in _TERMS:
        _TERMS[key] = _task_terms(task)
    return _TERMS[key]


_TERMS: dict[tuple[str, str, object], TaskTerms] = {}


def _task_terms(task: Task) -> TaskTerms:
    params = task.pddl_params
    roles = {
        "target": params.object_target,
        "destination": params.parent_target,
        "container": params.mrecep_target,
        "toggle": params.toggle_target,
    }
    role_types = {role: kind for role, kind in roles.items() if kind}
    seed = task.instruction
    words = [w for w, _, _ in word_spans(seed)]
    verbs = tuple(dict.fromkeys(lemma for w in words if (lemma := verb_lemma(w))))
    states = tuple(dict.fromkeys(w for w in words if w in _STATE_FORMS))
    seed_roles = tuple(role for role, kind in role_types.items() if mentions_of(seed, kind))
    return TaskTerms(
        seed=seed,
        role_types=role_types,
        seed_roles=seed_roles,
        verbs=verbs,
        state_words=states,
        state_kinds=frozenset(_STATE_FORMS[w] for w in states),
        seed_words=frozenset(words),
    )


def term_positions(terms: TaskTerms, text: str) -> dict[str, list[int]]:
    """Required term -> start offsets of its occurrences in `text` (each task verb in any inflection, each
    state word, each object role the seed names)."""
    positions: dict[str, list[int]] = {}
    words = word_spans(text)
    for lemma in terms.verbs:
        positions[f"verb:{lemma}"] = [s for w, s, _ in words if verb_lemma(w) == lemma]
    for state in terms.state_words:
        positions[f"state:{state}"] = [s for w, s, _ in words if w == state]
    for role in terms.seed_roles:
        positions[f"role:{role}"] = [m.start for m in mentions_of(text, terms.role_types[role])]
    return positions


def request_span(terms: TaskTerms, text: str) -> tuple[int, int] | None:
    """The request inside `text`: (first task-term start, start of the term that completes the request);
    None if a term is missing. The generator inserts its asides inside it, the verifier checks them there."""
    return span_of(term_positions(terms, text))


def span_of(positions: dict[str, list[int]]) -> tuple[int, int] | None:
    """`request_span` from `term_positions`' result (for a caller that already has them)."""
    firsts = [occ[0] for occ in positions.values() if occ]
    if not firsts or len(firsts) < len(positions):
        return None
    return min(firsts), max(firsts)


def state_kind(word: str) -> str | None:
    return _STATE_FORMS.get(word.lower())


def request_body(seed: str) -> str:
    """The seed as the body of a spoken request: `To see the ball.` -> `see the ball`.

    Only the framing changes (a leading "To", a gerund made imperative, the first letter lowercased, the
    final stop dropped); every task word stays as the annotator wrote it.
    """
    body = " ".join(seed.strip().split()).rstrip(" .!")
    body = _LEADING.sub("", body)
    first, _, rest = body.partition(" ")
    lemma = verb_lemma(first)
    if lemma and first.lower().endswith("ing") and lemma != "bring":
        first = lemma
    if not first.isupper() or len(first) == 1:
        first = first[:1].lower() + first[1:]
    return f"{first} {rest}".strip()


def noun_phrase(text: str, mention: Mention) -> tuple[int, str, str]:
    """The noun phrase around `mention`: (start, determiner, modifiers before the noun).

    "put a heated potato on" with the mention "potato" -> start of "a", "a", "heated".
    """
    before = text[: mention.start]
    tokens = list(re.finditer(r"[\w'-]+", before))[-3:]
    start = mention.start
    determiner = ""
    modifiers: list[str] = []
    for token in reversed(tokens):
        word = token.group(0)
        gap = before[token.end() : start]
        if gap.strip():  # punctuation between: outside the phrase
            break
        if word.lower() in _DETERMINERS:
            determiner = word
            start = token.start()
            break
        if verb_lemma(word) or word.lower() in {"and", "with", "in", "on", "to", "of", "from", "up", "off"}:
            break
        modifiers.insert(0, word)
        start = token.start()
    return start, determiner, " ".join(modifiers)
