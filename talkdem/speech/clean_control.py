"""The clean control and the request's phrase boundaries, as `rules-v2` wrote them.

`rules-v3` keeps `rules-v2`'s clean controls byte for byte (its step 1) and inserts its asides at the same
phrase boundaries inside the request. `rules-v2` itself is retired (`talkdem.speech.base.RETIRED`); this is
the part of it that `rules-v3` still speaks with, phrase banks included.

Step 1 (conversationalization) wraps the seed's own wording in a spoken request: a greeting, a request frame
(question, statement or imperative) and sometimes a closing; every task word stays as the annotator wrote it
(paper, prompt "Conversational Transformation").
"""

from __future__ import annotations

import random
import re
from dataclasses import dataclass

from talkdem.speech.lexicon import ALIASES, display_name, find_mentions, mentions_of
from talkdem.speech.task_terms import noun_phrase, request_body, request_span, state_kind, task_terms, verb_lemma
from talkdem.tasks import Task

__all__ = [
    "CLOSINGS",
    "GREETINGS",
    "GREETING_ENDS",
    "QUESTION_FRAMES",
    "STATEMENT_FRAMES",
    "Clean",
    "conversationalize",
    "insert",
    "insertion_points",
    "scene_candidates",
    "split",
]

GREETINGS = (
    "Hi",
    "Hello",
    "Hey",
    "Hi there",
    "Hello there",
    "Hey there",
    "Good morning",
    "Good afternoon",
    "Good evening",
    "Hello again",
    "Hiya",
    "Hi again",
    "Hello, dear",
)
# The greeting opens the request sentence ("Hi, could you ..."): the paper's clean controls are one sentence
# (sentence-level relevance 0.957), so a greeting of its own ("Hi!") would halve their relevance; a vocative
# ("Hello, robot") lowers the request's cosine to the seed most (0.70 to 0.77 against 0.85), so none is used.
GREETING_ENDS = (", ",)
# Frames around the request body; {body} is the seed wording, lowercased at the start.
QUESTION_FRAMES = (
    "could you {body}?",
    "can you {body} for me?",
    "would you {body}, please?",
    "do you think you could {body}?",
    "will you {body}?",
    "could you please {body}?",
    "would you be able to {body}?",
    "can you please {body}?",
)
# Statements and imperatives; half name no person, as the paper's clean controls have few pronouns (0.209 of
# nouns and pronouns).
STATEMENT_FRAMES = (
    "I'd like you to {body}.",
    "it would be great if you could {body}.",
    "when you have a moment, {body}.",
    "please {body}.",
    "{body}, please.",
    "{body} for me, would you?",
    "go ahead and {body}, please.",
    "{body} when you get a chance.",
    "please {body} now.",
    "{body}, thanks.",
    "{body}, thank you.",
    "please {body} today.",
    "kindly {body}.",
    "time to {body}, please.",
    "please {body}, thank you.",
    "{body}, if possible.",
    "please {body} at some point.",
)
# Closings stay inside the request sentence (", thanks.") in the frames above; none stands alone. The draw from
# this one-entry bank stays: it consumes the random generator, and the clean controls are its bytes.
CLOSINGS = ("",)

_BOUNDARY_WORDS = frozenset(
    {"on", "in", "into", "onto", "to", "inside", "under", "by", "with", "from", "and", "then", "while", "using"}
    | {"near", "next", "at", "over", "beside", "back", "away", "below", "above", "underneath"}
)
_PARTICLES = frozenset({"on", "off", "up", "down", "away", "back", "in", "out", "over"})
_UNMENTIONABLE = frozenset(
    {"StoveKnob", "ShowerGlass", "LaundryHamperLid", "Sink", "Lamp", "Faucet", "LightSwitch", "ShowerHead"}
)


def _cap(text: str) -> str:
    return text[:1].upper() + text[1:]


@dataclass(frozen=True)
class Clean:
    """A clean control split around the seed wording: prefix + body + end + closing."""

    prefix: str
    body: str
    end: str
    closing: str


def conversationalize(task: Task, rng: random.Random) -> str:
    """Greeting + request frame around the seed wording (+ an optional closing)."""
    body = request_body(task.instruction)
    greeting = rng.choice(GREETINGS) + rng.choice(GREETING_ENDS)
    # subordinate openings ("while carrying ...") read badly after "could you"
    frames = STATEMENT_FRAMES if body.lower().startswith(("while", "with")) else QUESTION_FRAMES + STATEMENT_FRAMES
    frame = rng.choice(frames)
    request = frame.format(body=body)
    request = _cap(request) if greeting.endswith(("! ", ". ")) or frame.startswith("{body}") else request
    if frame.startswith("{body}") and greeting.endswith(", "):
        request = request[:1].lower() + request[1:] if not body.split()[0].isupper() else request
    closing = rng.choice(CLOSINGS)
    return " ".join(p for p in (greeting + request, closing) if p)


def split(task: Task, clean: str) -> Clean:
    """`clean` around the task's seed wording."""
    body = request_body(task.instruction)
    at = clean.lower().find(body.lower())
    if at < 0:  # a clean control from another generator: treat its last sentence as the request
        return Clean("", clean.rstrip(".?!"), clean[len(clean.rstrip(".?!")) :], "")
    actual = clean[at : at + len(body)]
    rest = clean[at + len(body) :]
    stop = re.search(r"[.?!]", rest)
    cut = stop.end() if stop else len(rest)
    return Clean(clean[:at], actual, rest[:cut], rest[cut:].strip())


def scene_candidates(task: Task, pool: set[str] | None = None) -> list[str]:
    """Scene types the generator may bring in: not a task object, not worded in the seed, unambiguous."""
    terms = task_terms(task)
    seed = f" {task.instruction.lower()}"
    chosen = []
    for kind in sorted(set(task.scene.scene_objects) - terms.task_types - _UNMENTIONABLE):
        if pool is not None and kind not in pool:
            continue
        name = display_name(kind)
        named = find_mentions(name)
        if any(state_kind(word) for word in name.split()):  # "microwave" reads as a heating step
            continue
        if not named or named[0].types & terms.task_types:
            continue
        if any(f" {alias}" in seed for alias in ALIASES.get(kind, ())):
            continue
        chosen.append(kind)
    return chosen


def _target_start(task: Task, body: str) -> int | None:
    """Where the noun phrase of the first target mention in `body` starts."""
    found = mentions_of(body, task.pddl_params.object_target)
    if not found:
        return None
    start, _, _ = noun_phrase(body, found[0])
    return start


def insertion_points(task: Task, body: str) -> list[int]:
    """Word starts inside the request (after its first task term, up to its completing term)."""
    span = request_span(task_terms(task), body)
    first, last = span if span else (0, len(body))
    points = []
    for match in re.finditer(r"[\w']+", body):
        start = match.start()
        if not first < start <= last:
            continue
        preceded_by_comma = body[:start].rstrip().endswith(",")
        previous = re.findall(r"[\w']+", body[:start])[-1:]
        if previous and verb_lemma(previous[0]) and match.group(0).lower() in _PARTICLES:
            continue  # never split a phrasal verb: "turn, you know, on the lamp"
        if match.group(0).lower() in _BOUNDARY_WORDS or preceded_by_comma:
            points.append(start)
    target = _target_start(task, body)
    if target is not None and first < target <= last:
        points.append(target)
    if not points:
        points.append(last if last > first else len(body))
    return sorted(set(points))


def insert(body: str, at: int, text: str) -> str:
    """Insert `text` as a comma-delimited aside at a word start."""
    head = body[:at].rstrip()
    head = head[:-1] if head.endswith(",") else head
    return f"{head}, {text}, {body[at:]}"
