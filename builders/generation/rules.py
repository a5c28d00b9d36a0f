"""The `rules` generator: deterministic, seeded, scene-conditioned utterances without an LLM.

Step 1 (conversationalization) wraps the seed's own wording in a spoken request: a greeting, a request
frame (question, statement or imperative) and sometimes a closing; every task word stays as the annotator
wrote it (paper, prompt "Conversational Transformation").

Step 2 transforms that clean control with one pattern at one level (see `talk_dem.PATTERNS` for the level
definitions). Each transformation draws its wording from the phrase banks in `phrases.py` with a random
generator seeded per request, and draws competing and associated objects from the task's own scene list,
named by their lexical aliases. Choices are combined (where a pattern cue goes, which cue, which frame,
which object), so no two cells share one template.
"""

from __future__ import annotations

import random
import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass

from builders.generation import phrases as P
from builders.generation.base import CLEAN, GenerationRequest
from builders.lexicon import ALIASES, display_name, find_mentions, mentions_of
from builders.markers.variety import openers
from builders.task_terms import noun_phrase, request_body, state_kind, task_terms, verb_lemma
from builders.verification.checks import Context
from builders.verification.cues import EMPTY_SPEECH
from talkdem.skills import categories
from talkdem.tasks import Task

__all__ = ["RulesGenerator"]

_BOUNDARY_WORDS = frozenset(
    {"on", "in", "into", "onto", "to", "inside", "under", "by", "with", "from", "and", "then", "while", "using"}
    | {"near", "next", "at", "over", "beside", "back", "away", "below", "above", "underneath"}
)
_PARTICLES = frozenset({"on", "off", "up", "down", "away", "back", "in", "out", "over"})
_FOOD = P.OBJECT_KINDS[0]
_UNMENTIONABLE = frozenset(
    {"StoveKnob", "ShowerGlass", "LaundryHamperLid", "Sink", "Lamp", "Faucet", "LightSwitch", "ShowerHead"}
)


def _cap(text: str) -> str:
    return text[:1].upper() + text[1:]


def _article(word: str) -> str:
    return "an" if word[:1].lower() in "aeiou" else "a"


# Substituted nouns that take no "a": mass nouns and plural display names ("some bread", "some keys").
_NO_INDEFINITE = frozenset({"bread", "toilet paper", "soap", "lettuce", "keys"})


def _lower_first(text: str) -> str:
    """Lowercase the first letter unless the first word is "I" or all capitals (a name like "TV")."""
    first = text.split(" ", 1)[0]
    return text if first in {"I", "I'm", "I'd", "I'll"} or first.isupper() else text[:1].lower() + text[1:]


@dataclass
class _Clean:
    """A clean control split around the seed wording: prefix + body + end + closing."""

    prefix: str
    body: str
    end: str
    closing: str

    def join(self, body: str | None = None, after_end: Sequence[str] = (), after_closing: Sequence[str] = ()) -> str:
        text = self.prefix + (self.body if body is None else body) + self.end
        parts = [text, *after_end, self.closing, *after_closing]
        return " ".join(p.strip() for p in parts if p.strip())


class RulesGenerator:
    """Rule-based generator: same request seed, same utterance, byte for byte."""

    name = "rules"
    prompt_version = P.PHRASES_VERSION

    def generate(self, requests: Sequence[GenerationRequest]) -> list[str]:
        return [self.generate_one(r) for r in requests]

    def generate_one(self, request: GenerationRequest) -> str:
        rng = random.Random(request.seed)
        if request.pattern == CLEAN:
            return self.conversationalize(request.task, rng)
        transform = self._transforms()[request.pattern]
        return transform(request.task, self._split(request.task, request.clean), request.level, rng)

    def _transforms(self) -> dict[str, Callable[[Task, _Clean, int, random.Random], str]]:
        return {
            "referential_imprecision": self.referential_imprecision,
            "object_substitution": self.object_substitution,
            "empty_speech": self.empty_speech,
            "topic_drift": self.topic_drift,
            "intrusion": self.intrusion,
        }

    # --- step 1 --------------------------------------------------------------------------------------------
    def conversationalize(self, task: Task, rng: random.Random) -> str:
        """Greeting + request frame around the seed wording (+ an optional closing)."""
        body = request_body(task.instruction)
        greeting = rng.choice(P.GREETINGS) + rng.choice(P.GREETING_ENDS)
        # subordinate openings ("while carrying ...") read badly after "could you"
        frames = (
            P.STATEMENT_FRAMES if body.lower().startswith(("while", "with")) else P.QUESTION_FRAMES + P.STATEMENT_FRAMES
        )
        frame = rng.choice(frames)
        request = frame.format(body=body)
        request = _cap(request) if greeting.endswith(("! ", ". ")) or frame.startswith("{body}") else request
        if frame.startswith("{body}") and greeting.endswith(", "):
            request = request[:1].lower() + request[1:] if not body.split()[0].isupper() else request
        closing = rng.choice(P.CLOSINGS)
        return " ".join(p for p in (greeting + request, closing) if p)

    def _split(self, task: Task, clean: str) -> _Clean:
        body = request_body(task.instruction)
        at = clean.lower().find(body.lower())
        if at < 0:  # a clean control from another generator: treat its last sentence as the request
            return _Clean("", clean.rstrip(".?!"), clean[len(clean.rstrip(".?!")) :], "")
        actual = clean[at : at + len(body)]
        rest = clean[at + len(body) :]
        stop = re.search(r"[.?!]", rest)
        cut = stop.end() if stop else len(rest)
        return _Clean(clean[:at], actual, rest[:cut], rest[cut:].strip())

    # --- helpers ---------------------------------------------------------------------------------------------
    @staticmethod
    def _target_np(task: Task, body: str) -> tuple[int, int, str, str, str] | None:
        """(start, end, determiner, modifiers, noun as written) of the first target mention in the body."""
        found = mentions_of(body, task.pddl_params.object_target)
        if not found:
            return None
        mention = found[0]
        start, det, mods = noun_phrase(body, mention)
        return start, mention.end, det, mods, body[mention.start : mention.end]

    @staticmethod
    def _np(det: str, mods: str, head: str) -> str:
        """A noun phrase with the target's determiner and modifiers around another head, articles agreeing."""
        if det.lower() in {"a", "an"}:
            det = "some" if head.lower() in _NO_INDEFINITE else _article(mods or head)
            det = det.capitalize() if det and det[:1].isupper() else det
        words = [w for w in (det or "the", mods, head) if w]
        return " ".join(words)

    @staticmethod
    def _name(task: Task, noun: str | None) -> str:
        return f"the {noun or display_name(task.pddl_params.object_target)}"

    @staticmethod
    def _scene_candidates(task: Task, pool: set[str] | None = None) -> list[str]:
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

    def _competitors(self, task: Task, rng: random.Random, count: int) -> list[str]:
        pickupable = set(categories().pickupable)
        candidates = self._scene_candidates(task, pickupable)
        target = task.pddl_params.object_target
        same_kind = [c for c in candidates if any(target in k and c in k for k in P.OBJECT_KINDS)]
        others = [c for c in candidates if c not in same_kind]
        rng.shuffle(same_kind)
        rng.shuffle(others)
        return (same_kind + others)[:count]

    @staticmethod
    def _insertion_points(task: Task, body: str) -> list[int]:
        """Word starts inside the request (after its first task term, up to its completing term)."""
        span = Context(task, CLEAN, 0, body).request_span
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
        np = RulesGenerator._target_np(task, body)
        if np and first < np[0] <= last:
            points.append(np[0])
        if not points:
            points.append(last if last > first else len(body))
        return sorted(set(points))

    @staticmethod
    def _insert(body: str, at: int, text: str) -> str:
        """Insert `text` as a comma-delimited aside at a word start."""
        head = body[:at].rstrip()
        head = head[:-1] if head.endswith(",") else head
        return f"{head}, {text}, {body[at:]}"

    # --- step 2: the five patterns -------------------------------------------------------------------------------
    def referential_imprecision(self, task: Task, clean: _Clean, level: int, rng: random.Random) -> str:
        """L1 vague expression + immediate self-clarification; L2 delayed clarification; L3 circumlocution."""
        body = clean.body
        np = self._target_np(task, body)
        vague = rng.choice(P.VAGUE_NOUNS)
        if np is None:  # the seed does not name its target: a vague aside, then the name
            name = self._name(task, None)
            circ = rng.choice(P.CIRCUMLOCUTIONS.get(task.pddl_params.object_target, P.GENERIC_CIRCUMLOCUTIONS))
            aside = {
                1: [f"Oh, and the {vague}, {name}, don't forget that."],
                2: [f"Oh, and the {vague}, don't forget that.", f"{_cap(name)}, I mean."],
                3: [f"Oh, and the {vague}, {circ}, that one, don't forget it.", f"{_cap(name)}, that's the word."],
            }[level]
            return clean.join(after_end=aside)
        start, end, det, mods, noun = np
        name = self._name(task, noun)
        vague_np = self._np(det if det.lower() not in {"the"} or rng.random() < 0.5 else "that", mods, vague)
        if level == 1:
            clar = rng.choice(P.IMMEDIATE_CLARIFIERS).format(vague=vague_np, name=name, Name=_cap(name))
            if ". " in clar:  # "that thing. The book" must stay within the sentence for L1
                clar = clar.replace(". ", ", ")
            return clean.join(body=body[:start] + clar + body[end:])
        if level == 2:
            later = rng.choice(P.DELAYED_CLARIFICATIONS).format(name=name, Name=_cap(name))
            return clean.join(body=body[:start] + vague_np + body[end:], after_end=[later])
        circ = rng.choice(P.CIRCUMLOCUTIONS.get(task.pddl_params.object_target, P.GENERIC_CIRCUMLOCUTIONS))
        second = rng.choice(P.SECOND_VAGUE)
        stand_in = f"{vague_np}, {circ}, {second},"
        tail = body[end:].lstrip(" ,")
        naming = rng.choice(P.FINAL_NAMING).format(name=name, Name=_cap(name))
        lead = rng.choice([x for x in P.WORD_SEARCH_LEADS if x.lower() not in openers(naming)])
        search = [f"{lead}, {rng.choice(P.WORD_SEARCH)}.", rng.choice(P.WORD_SEARCH_SELF)]
        rng.shuffle(search)
        search = search if rng.random() < 0.65 else search[:1]  # pronoun share near the paper's 0.351
        return clean.join(body=f"{body[:start]}{stand_in} {tail}".rstrip(" ,"), after_end=[*search, naming])

    def object_substitution(self, task: Task, clean: _Clean, level: int, rng: random.Random) -> str:
        """L1 wrong in-scene object corrected at once; L2 corrected after the request; L3 repeated substitution."""
        body = clean.body
        np = self._target_np(task, body)
        comps = self._competitors(task, rng, 2)
        if not comps:
            return clean.join()  # nothing to substitute with; the verifier records the failure
        comp = f"the {display_name(comps[0])}"
        comp2 = f"the {display_name(comps[1])}" if len(comps) > 1 else comp
        if np is None:  # the seed does not name its target: substitute in an aside
            name = self._name(task, None)
            fmt = {"comp": comp, "comp2": comp2, "name": name, "Name": _cap(name)}
            aside = {
                1: [f"And {comp}, no, sorry, {name}, don't forget that."],
                2: [f"And {comp}, don't forget that.", rng.choice(P.DELAYED_REPAIRS).format(**fmt)],
                3: [f"And {comp}, {comp2}, don't forget that.", rng.choice(P.FINAL_REPAIRS).format(**fmt)],
            }[level]
            return clean.join(after_end=aside)
        start, end, det, mods, noun = np
        name = self._name(task, noun)
        wrong = self._np(det, mods, display_name(comps[0]))
        fmt = {"comp": comp, "comp2": comp2, "name": name, "Name": _cap(name)}
        if level == 1:
            repair = rng.choice(P.IMMEDIATE_REPAIRS).format(**fmt)
            return clean.join(body=f"{body[:start]}{wrong}, {repair}{body[end:]}")
        if level == 2:
            later = rng.choice(P.DELAYED_REPAIRS).format(**fmt)
            return clean.join(body=body[:start] + wrong + body[end:], after_end=[later])
        if len(comps) > 1:
            second = rng.choice(P.SECOND_SUBSTITUTIONS).format(**fmt)
            new_body = f"{body[:start]}{wrong}, {second},{body[end:]}"
            final = rng.choice(P.FINAL_REPAIRS).format(**fmt)
        else:
            new_body = body[:start] + wrong + body[end:]
            final = P.FINAL_REPAIRS[0].format(**fmt)
        return clean.join(body=new_body, after_end=[final])

    def empty_speech(self, task: Task, clean: _Clean, level: int, rng: random.Random) -> str:
        """L1 one empty expression inside the request; L2 two inside, three in all; L3 more, with empty sentences."""
        body = clean.body
        points = self._insertion_points(task, body)
        inside = {1: 1, 2: 2, 3: rng.choice((3, 4))}[level]
        # each cluster: a known filler or stock phrase, sometimes with a second discourse marker
        heads = rng.sample(P.DISCOURSE_FILLERS, inside)
        if level == 1 and rng.random() < 0.5:  # the paper's Level 1 pronoun share rises to 0.370
            heads = [rng.choice(("you know", "you see"))]
        clusters = []
        for i, word in enumerate(heads):
            if rng.random() < 0.25:
                word = rng.choice(P.FILLERS)
            elif rng.random() < {1: 0.45, 2: 0.35, 3: 0.3}[level]:
                extra = rng.choice([e for e in P.DISCOURSE_EXTRAS if e != word])
                word = f"{extra}, {word}" if i % 2 else f"{word}, {extra}"
            clusters.append(word)
        chosen = sorted(rng.choices(points, k=inside), reverse=True)
        stacked: dict[int, list[str]] = {}
        for at, filler in zip(chosen, clusters, strict=True):
            stacked.setdefault(at, []).append(filler)
        for at in sorted(stacked, reverse=True):
            body = self._insert(body, at, ", ".join(stacked[at]))
        count = {1: 0, 2: 1, 3: 2}[level]
        leads = rng.sample(P.EMPTY_LEADS, count)
        cores = rng.sample(P.EMPTY_CORES, count)
        sentences = []
        for lead, core in zip(leads, cores, strict=True):
            sentence = f"{lead}, {core}{rng.choice(P.EMPTY_TAGS)}."
            if not EMPTY_SPEECH.search(sentence):  # the verifier must recognise every empty sentence
                # "you see" and "like" count only between commas: end with a tag that counts anywhere
                sentence = f"{lead}, {core}, {rng.choice(('you know', 'sort of', 'kind of', 'and all that'))}."
            sentences.append(sentence)
        if level == 1 and rng.random() < 0.4:  # a discourse marker opens the utterance
            lead = rng.choice(("Well", "Oh", "Um", "So", "Right"))
            return f"{lead}, {_lower_first(clean.join(body=body))}"
        return clean.join(body=body, after_end=sentences)

    def topic_drift(self, task: Task, clean: _Clean, level: int, rng: random.Random) -> str:
        """L1 one remark on another scene object; L2 on to a memory; L3 through memories to unrelated topics."""
        candidates = self._scene_candidates(task)
        rng.shuffle(candidates)
        # furniture and keepsakes make likelier memories than groceries: food goes last
        candidates = [c for c in candidates if c not in _FOOD] + [c for c in candidates if c in _FOOD]
        objects = candidates[: {1: 1, 2: 2, 3: 3}[level]]
        stages = [P.DRIFT_NEAR] + [P.DRIFT_MEMORY] * (len(objects) - 1)
        memories = rng.sample(P.DRIFT_MEMORY, len(objects))
        texts = []
        for i, (kind, bank) in enumerate(zip(objects, stages, strict=True)):
            template = rng.choice(bank) if i == 0 else memories[i]
            texts.append(self._fill(template, display_name(kind)))
        if level == 3:  # four sentences in all: the paper's Level 3 relevance (0.379) leaves room for no more
            texts += rng.sample(P.DRIFT_FAR, 1)
        own = {t.split(",", 1)[0] + ", " for t in texts}  # lead-ins some templates start with
        leads = rng.sample([x for x in P.DRIFT_LEADS if x not in own], len(texts))  # none twice in one utterance
        sentences = [self._led(rng, text, lead) for text, lead in zip(texts, leads, strict=True)]
        return clean.join(after_closing=sentences)

    @staticmethod
    def _led(rng: random.Random, sentence: str, lead: str) -> str:
        """A sentence with an optional discourse lead-in ("Oh, we got ..."), never before another lead-in."""
        opener = sentence.split(",", 1)[0]
        if ("," in sentence and len(opener.split()) <= 2) or rng.random() < 0.35:
            return sentence
        if not sentence.startswith(("I ", "I'", "Dad ", "Aunt ", "Everybody", "Grandad ", "Margaret")):
            sentence = sentence[:1].lower() + sentence[1:]
        return _cap(lead + sentence)

    @staticmethod
    def _fill(template: str, name: str) -> str:
        plural = name.endswith("s") and not name.endswith("ss")
        words = {
            "the": f"the {name}",
            "a": f"some {name}" if plural or name in _NO_INDEFINITE else f"{_article(name)} {name}",
            "that": f"{'those' if plural else 'that'} {name}",
        }
        words.update({_cap(k): _cap(v) for k, v in words.items()})
        text = template.format(**words)
        return _cap(text)

    @staticmethod
    def _resumption(rng: random.Random, before: str) -> str:
        """A way back to the request whose lead-in the intrusion has not just used ("Never mind" twice)."""
        used = set(openers(f"{before} x"))
        return rng.choice([r for r in P.RESUMPTIONS if (openers(f"{r}x") or [""])[0] not in used])

    def intrusion(self, task: Task, clean: _Clean, level: int, rng: random.Random) -> str:
        """L1 a short off-task thought mid-request; L2 a longer one; L3 two fragmented ones and a restatement."""
        body = clean.body
        points = self._insertion_points(task, body)
        at = points[len(points) // 2]
        head = body[:at].rstrip().rstrip(",")
        rest = body[at:]
        if level == 1:
            thought = rng.choice(P.INTRUSION_SHORT)
            return clean.join(body=f"{head}, {thought} {self._resumption(rng, thought)}{rest}")
        if level == 2:
            thought = f"{rng.choice(P.INTRUSION_SHORT)} {rng.choice(P.INTRUSION_FOLLOW)}"
            return clean.join(body=f"{head}, {thought} {self._resumption(rng, thought)}{rest}")
        fragments: list[str] = []
        for candidate in rng.sample(P.INTRUSION_FRAGMENTS, len(P.INTRUSION_FRAGMENTS)):
            if not set(openers(candidate)) & set(openers(" ".join(fragments))):  # "Margaret, ..." once
                fragments.append(candidate)
            if len(fragments) == 3:
                break
        fragment = " ".join(fragments[: rng.choice((2, 3, 3))])  # below Level 2's relevance by a margin
        span = Context(task, CLEAN, 0, body).request_span
        start = span[0] if span else 0
        restated = _lower_first(body[start:at].strip().rstrip(","))
        restate = rng.choice(P.RESTATEMENTS).format(restate=restated)
        thought = rng.choice(P.INTRUSION_SHORT)
        resume = self._resumption(rng, f"{restate}, {thought}")
        return clean.join(body=f"{head}. {fragment} {restate}, {thought} {resume}{rest}")
