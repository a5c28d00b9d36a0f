"""Deterministic verification of one generated utterance (paper, appendix "Rule-Constrained Generation").

Every check is a small function `check(ctx) -> bool` named after what it tests; `verify()` runs the checks
that apply to the pattern and level and returns `{"passed": bool, "failed_checks": [...]}`.

Terms: the *request* spans from the first task-term occurrence to the point where the last required term
is first mentioned (the request is complete there). Task terms are the seed's task verbs, the object of
every role the seed names (target, destination, container, lamp) and the seed's state words.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

from builders.markers.variety import repeated_opener
from talkdem.schema import CLEAN, LEVELS
from talkdem.speech.cues import EMPTY_SPEECH, REPAIR, SENTENCE_BREAK, VAGUE, find_all
from talkdem.speech.lexicon import find_mentions, mentions_of, word_spans
from talkdem.speech.task_terms import TaskTerms, span_of, state_kind, task_terms, term_positions
from talkdem.tasks import Task

__all__ = ["CHECKS", "Context", "checks_for", "verify"]


@dataclass
class Context:
    """One utterance to verify, with its task and what the checks compute from it."""

    task: Task
    pattern: str
    level: int
    text: str
    terms: TaskTerms = field(init=False)

    def __post_init__(self) -> None:
        self.terms = task_terms(self.task)

    # --- task-term occurrences -------------------------------------------------------------------------
    @cached_property
    def term_positions(self) -> dict[str, list[int]]:
        """Required term -> start offsets of its occurrences in the utterance."""
        return term_positions(self.terms, self.text)

    @cached_property
    def request_span(self) -> tuple[int, int] | None:
        """(first task-term start, start of the term that completes the request); None if a term is missing."""
        return span_of(self.term_positions)

    def target_positions(self) -> list[int]:
        return [m.start for m in mentions_of(self.text, self.terms.role_types["target"])]

    def foreign_mentions(self) -> list[tuple[int, frozenset[str]]]:
        """Object mentions that name no task object and whose wording the seed does not contain."""
        seed = self.terms.seed.lower()
        task_types = self.terms.task_types
        found = []
        for m in find_mentions(self.text):
            if m.types & task_types or f" {m.alias}" in f" {seed}":
                continue
            found.append((m.start, m.types))
        return found

    def sentence_breaks(self, start: int, end: int) -> int:
        return sum(1 for s, _ in find_all(SENTENCE_BREAK, self.text) if start <= s < end)

    def words_between(self, start: int, end: int) -> list[str]:
        return [w for w, s, _ in word_spans(self.text) if start <= s < end]


Check = Callable[[Context], bool]


# --- task preservation -------------------------------------------------------------------------------------
def task_verb(ctx: Context) -> bool:
    """Every task verb of the seed survives (any inflection)."""
    return all(ctx.term_positions[f"verb:{lemma}"] for lemma in ctx.terms.verbs)


def _role_check(role: str) -> Check:
    def check(ctx: Context) -> bool:
        if role not in ctx.terms.seed_roles:
            return True
        return bool(mentions_of(ctx.text, ctx.terms.role_types[role]))

    check.__name__ = {"target": "target_object", "toggle": "toggle_object"}.get(role, role)
    check.__doc__ = f"The {role} object is named (by any of its aliases) when the seed names it."
    return check


target_object = _role_check("target")
destination = _role_check("destination")
container = _role_check("container")
toggle_object = _role_check("toggle")


def state_words(ctx: Context) -> bool:
    """Every state word of the seed (hot, heated, chilled, rinsed, sliced, ...) survives verbatim."""
    return all(ctx.term_positions[f"state:{w}"] for w in ctx.terms.state_words)


def no_added_state(ctx: Context) -> bool:
    """No state of another kind is introduced ("it's cold out" in a heating task changes the task)."""
    kinds = {k for w, _, _ in word_spans(ctx.text) if (k := state_kind(w))}
    return kinds <= set(ctx.terms.state_kinds)


def scene_objects(ctx: Context) -> bool:
    """Every object mentioned beyond the seed's own wording is present in the task's scene."""
    scene = set(ctx.task.scene.scene_objects)
    return all(types & scene for _, types in ctx.foreign_mentions())


def no_dashes_colons(ctx: Context) -> bool:
    """Ordinary spoken punctuation: no dashes or colons beyond those of the seed itself."""
    text = ctx.text
    for token in ctx.terms.seed.split():
        if any(c in token for c in "-:–—"):
            text = text.replace(token.strip(".,!?"), " ")
    return not any(c in text for c in "-:–—")


def varied_openers(ctx: Context) -> bool:
    """No two sentences open with the same lead-in ("Oh, the name. Oh, the apple."): a speaker varies them.

    The phrase banks combine freely, so a few draws repeat a lead-in; the unranked build happened to keep
    none, but a ranking model prefers them (repetition is predictable), so the ranked build kept 5 of 4,500."""
    return not repeated_opener(ctx.text)


# --- clean control ------------------------------------------------------------------------------------------
def clean_no_pattern(ctx: Context) -> bool:
    """The clean control shows no communication pattern: no vague reference, repair, filler or break."""
    if VAGUE.search(ctx.text) or REPAIR.search(ctx.text) or EMPTY_SPEECH.search(ctx.text):
        return False
    span = ctx.request_span
    return span is None or ctx.sentence_breaks(*span) == 0


# --- Referential Imprecision -------------------------------------------------------------------------------
def _vague_before_name(ctx: Context) -> tuple[list[tuple[int, int]], int] | None:
    targets = ctx.target_positions()
    if not targets:
        return None
    name = targets[0]
    vague = [(s, e) for s, e in find_all(VAGUE, ctx.text) if s < name]
    return (vague, name) if vague else None


def ri_vague_first(ctx: Context) -> bool:
    """The target is first referred to by a nonspecific expression and named later."""
    return _vague_before_name(ctx) is not None


def ri_immediate_clarification(ctx: Context) -> bool:
    """L1: the name follows the vague expression at once (within six words, same sentence)."""
    found = _vague_before_name(ctx)
    if found is None:
        return False
    vague, name = found
    last_end = vague[-1][1]
    return len(ctx.words_between(last_end, name)) <= 6 and ctx.sentence_breaks(last_end, name) == 0


def ri_delayed_clarification(ctx: Context) -> bool:
    """L2: the name comes later: another task term or a sentence boundary lies between."""
    found = _vague_before_name(ctx)
    if found is None:
        return False
    vague, name = found
    first = vague[0][0]
    other_terms = any(first < s < name for key, occ in ctx.term_positions.items() if key != "role:target" for s in occ)
    return other_terms or ctx.sentence_breaks(first, name) > 0


def ri_circumlocution(ctx: Context) -> bool:
    """L3: several vague references or a description stand in for the name for at least eight words."""
    found = _vague_before_name(ctx)
    if found is None:
        return False
    vague, name = found
    return len(vague) >= 2 and len(ctx.words_between(vague[0][0], name)) >= 8


# --- Object Substitution -----------------------------------------------------------------------------------
def _competitors_before_target(ctx: Context) -> tuple[list[int], int] | None:
    targets = ctx.target_positions()
    if not targets:
        return None
    scene = set(ctx.task.scene.scene_objects)
    comps = [s for s, types in ctx.foreign_mentions() if types & scene]
    last_target = targets[-1]
    before = [s for s in comps if s < last_target]
    if not before or before[0] > targets[0]:
        return None
    return before, last_target


def os_competitor_first(ctx: Context) -> bool:
    """A competing in-scene object is named before the target."""
    return _competitors_before_target(ctx) is not None


def os_correction(ctx: Context) -> bool:
    """A self-correction follows the competing object and leads back to the target."""
    found = _competitors_before_target(ctx)
    if found is None:
        return False
    comps, last_target = found
    return any(comps[0] < s <= last_target for s, _ in find_all(REPAIR, ctx.text))


def os_immediate_correction(ctx: Context) -> bool:
    """L1: the correction comes at once (target within eight words of the competitor, same sentence)."""
    found = _competitors_before_target(ctx)
    if found is None:
        return False
    comps, _ = found
    after = [s for s in ctx.target_positions() if s > comps[0]]
    return (
        bool(after) and len(ctx.words_between(comps[0], after[0])) <= 8 and not ctx.sentence_breaks(comps[0], after[0])
    )


def os_delayed_correction(ctx: Context) -> bool:
    """L2: the wrong object stays in the request; the correction comes after another term or sentence."""
    found = _competitors_before_target(ctx)
    if found is None:
        return False
    comps, last_target = found
    others = any(
        comps[0] < s < last_target for key, occ in ctx.term_positions.items() if key != "role:target" for s in occ
    )
    return others or ctx.sentence_breaks(comps[0], last_target) > 0


def os_repeated_substitution(ctx: Context) -> bool:
    """L3: the wrong object persists: two or more competitor mentions and two or more repairs."""
    found = _competitors_before_target(ctx)
    if found is None:
        return False
    comps, last_target = found
    repairs = [s for s, _ in find_all(REPAIR, ctx.text) if comps[0] < s <= last_target]
    return len(comps) >= 2 and len(repairs) >= 2


# --- Empty Speech -------------------------------------------------------------------------------------------
_ES_INSIDE = {1: 1, 2: 2, 3: 3}
_ES_TOTAL = {1: 1, 2: 3, 3: 5}


def es_interrupts_request(ctx: Context) -> bool:
    """Empty speech sits inside the request (between its first and last task term), more at higher levels."""
    span = ctx.request_span
    if span is None:
        return False
    inside = [s for s, _ in find_all(EMPTY_SPEECH, ctx.text) if span[0] < s < span[1]]
    return len(inside) >= _ES_INSIDE[ctx.level]


def es_amount(ctx: Context) -> bool:
    """The utterance holds enough empty speech for its level (1, 3, 5 expressions)."""
    return len(find_all(EMPTY_SPEECH, ctx.text)) >= _ES_TOTAL[ctx.level]


# --- Topic Drift ---------------------------------------------------------------------------------------------
_TD_SENTENCES = {1: 1, 2: 2, 3: 4}
_TD_OBJECTS = {1: 1, 2: 2, 3: 3}


def _drift_start(ctx: Context) -> int | None:
    span = ctx.request_span
    if span is None:
        return None
    breaks = [s for s, _ in find_all(SENTENCE_BREAK, ctx.text) if s >= span[1]]
    return breaks[0] + 1 if breaks else None


def td_drift_after_request(ctx: Context) -> bool:
    """The complete request comes first, then off-task sentences (1, 2, 4 or more by level)."""
    start = _drift_start(ctx)
    if start is None:
        return False
    drift = ctx.text[start:]
    return len(find_all(SENTENCE_BREAK, drift)) >= _TD_SENTENCES[ctx.level] and bool(drift.strip())


def td_scene_associations(ctx: Context) -> bool:
    """The drift brings in scene objects beyond the task's (1, 2, 3 distinct by level), all in the scene."""
    start = _drift_start(ctx)
    if start is None:
        return False
    scene = set(ctx.task.scene.scene_objects)
    distinct = {types & scene for s, types in ctx.foreign_mentions() if s >= start and types & scene}
    return len(distinct) >= _TD_OBJECTS[ctx.level]


# --- Intrusion -------------------------------------------------------------------------------------------------
_IN_BREAKS = {1: 1, 2: 1, 3: 2}
_IN_WORDS = {1: 3, 2: 6, 3: 10}


def in_interrupts_request(ctx: Context) -> bool:
    """An off-task thought (new words, a sentence of its own) breaks into the unfinished request."""
    span = ctx.request_span
    if span is None:
        return False
    novel = [w for w in ctx.words_between(*span) if w not in ctx.terms.seed_words]
    return ctx.sentence_breaks(*span) >= _IN_BREAKS[ctx.level] and len(novel) >= _IN_WORDS[ctx.level]


def in_resumed(ctx: Context) -> bool:
    """After the intrusion the request resumes with task content not yet given."""
    span = ctx.request_span
    if span is None:
        return False
    breaks = [s for s, _ in find_all(SENTENCE_BREAK, ctx.text) if span[0] <= s < span[1]]
    if not breaks:
        return False
    return any(occ and occ[0] > breaks[0] for occ in ctx.term_positions.values())


# --- registry ---------------------------------------------------------------------------------------------------
COMMON: tuple[Check, ...] = (
    task_verb,
    target_object,
    destination,
    container,
    toggle_object,
    state_words,
    no_added_state,
    scene_objects,
    no_dashes_colons,
    varied_openers,
)
PATTERN_CHECKS: dict[str, dict[int, tuple[Check, ...]]] = {
    CLEAN: {0: (clean_no_pattern,)},
    "referential_imprecision": {
        1: (ri_vague_first, ri_immediate_clarification),
        2: (ri_vague_first, ri_delayed_clarification),
        3: (ri_vague_first, ri_circumlocution),
    },
    "object_substitution": {
        1: (os_competitor_first, os_correction, os_immediate_correction),
        2: (os_competitor_first, os_correction, os_delayed_correction),
        3: (os_competitor_first, os_correction, os_repeated_substitution),
    },
    "empty_speech": {lvl: (es_interrupts_request, es_amount) for lvl in LEVELS},
    "topic_drift": {lvl: (td_drift_after_request, td_scene_associations) for lvl in LEVELS},
    "intrusion": {lvl: (in_interrupts_request, in_resumed) for lvl in LEVELS},
}
CHECKS: dict[str, Check] = {
    check.__name__: check
    for group in (COMMON, *(c for lv in PATTERN_CHECKS.values() for c in lv.values()))
    for check in group
}


def checks_for(pattern: str, level: int) -> tuple[Check, ...]:
    if pattern not in PATTERN_CHECKS:
        raise ValueError(f"unknown pattern '{pattern}': expected one of {', '.join(PATTERN_CHECKS)}")
    levels = PATTERN_CHECKS[pattern]
    if level not in levels:
        raise ValueError(f"pattern '{pattern}' has levels {', '.join(map(str, levels))}, not {level}")
    return COMMON + levels[level]


def verify(task: Task, pattern: str, level: int, text: str) -> dict[str, Any]:
    """`{"passed": bool, "failed_checks": [names]}` for one utterance (level 0 for `clean`)."""
    if pattern == CLEAN:
        level = 0
    ctx = Context(task, pattern, level, text)
    failed = [check.__name__ for check in checks_for(pattern, level) if not check(ctx)]
    return {"passed": not failed, "failed_checks": failed}
