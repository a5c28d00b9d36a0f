"""The `rules-v3` generator: one speaker per task, typed fills, forms drawn from ranges, K candidates.

Step 1 (the clean control) is `rules-v2`'s conversationalization (`clean_control`), so the clean controls do not
change, with one fix: a seed that does not name its target (ALFRED annotators wrote "the cup" for toilet paper,
"gray try" for a plate with a knife) gets one plain sentence naming it ("It's the toilet paper I'm after."), so
that a pattern variant never gives away a target the clean control withholds, and never asks for a second object.

Step 2 draws the form of each utterance from `forms.FORMS` (how many sentences, where the material sits), its
wording from the parts in `phrases_v3.py`, the speaker from `personas.persona_for(task_id)`, and every object
it brings in from the task's scene through the typed lexicon (`object_kinds`): a frame declares the kinds of
thing it can take, so a memory is never about a butter knife behind which children hid.

`generate_candidates` draws K utterances per request, each with its own seed derived from the request's; the
dataset build keeps those that pass verification and ranks them (`builders/generation/ranking.py`).
"""

from __future__ import annotations

import random
import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace

from talkdem.skills import categories
from talkdem.speech import clean_control
from talkdem.speech import phrases_v3 as V
from talkdem.speech.base import CLEAN, GenerationRequest, derive_seed
from talkdem.speech.cues import EMPTY_SPEECH, REPAIR, openers
from talkdem.speech.forms import chance, draw
from talkdem.speech.lexicon import mentions_of
from talkdem.speech.object_kinds import Noun, kinds_of, noun
from talkdem.speech.personas import Persona, persona_for
from talkdem.speech.task_terms import noun_phrase, request_span, task_terms
from talkdem.tasks import Task

__all__ = ["DEFAULT_CANDIDATES", "RulesV3Generator", "unnamed_target_tasks"]

DEFAULT_CANDIDATES = 4
"""Candidates drawn per request (the build ranks those that pass verification)."""

_CLOSING = re.compile(r", (thanks|thank you)([.?!])$")
_POST_NOUN = re.compile(r"^ (slices?|pieces?)\b")
_STATE_PARTICLE = re.compile(r"\b(a|an|the|some)\s+((?:[\w'-]+\s+){0,2}?(?:off|up)\s+)$", re.IGNORECASE)


def _cap(text: str) -> str:
    return text[:1].upper() + text[1:]


def _article(word: str) -> str:
    return "an" if word[:1].lower() in "aeiou" else "a"


# First words a lead-in ("Oh, ", "You know, ") may lowercase; anything else (a name, a title such as "Mrs",
# "I", "Christmas") keeps its capital.
_LOWERABLE = frozenset(
    ("the", "my", "we", "we've", "we'd", "our", "there", "that", "those", "this", "these", "some", "a", "an", "it",
     "it's", "at", "funny", "years", "all", "goodness", "such", "never", "still", "time", "anyway", "oh", "ah", "so",
     "yes", "now", "right", "well")
)  # fmt: skip


# Words that open or resume a sentence; one utterance says each at most once at a sentence's start or in a
# lead-in ("Right, yes, ... Sorry, yes, ..." reads as a loop of the generator).
_LEAD_WORDS = frozenset(
    ("oh", "yes", "so", "now", "right", "anyway", "anyhow", "sorry", "ah", "well", "goodness", "hmm", "um", "er", "no",
     "wait")
)  # fmt: skip


def _lead_words(text: str) -> set[str]:
    """The lead words and short lead-ins said in `text`'s comma-delimited chunks ("Oh, dear me," -> oh, dear me)."""
    chunks = [c.strip() for c in re.split(r"[,.?!]", text.lower()) if 0 < len(c.split()) <= 2]
    return {w for chunk in chunks for w in re.findall(r"[\w']+", chunk)} & _LEAD_WORDS | set(chunks)


def _after_lead(text: str) -> str:
    """`text` as it reads after a lead-in: its first letter lowercased only when the first word is a common word."""
    first = re.split(r"[\s,.?!]", text, maxsplit=1)[0]
    return text[:1].lower() + text[1:] if first.lower() in _LOWERABLE else text


def unnamed_target_tasks(tasks: Sequence[Task]) -> list[str]:
    """Ids of the tasks whose seed names no target (the clean control then names it once)."""
    return [t.task_id for t in tasks if "target" not in task_terms(t).seed_roles]


@dataclass
class _Parts:
    """A clean control taken apart: prefix + body + end, the target-naming sentence, the closing thanks."""

    prefix: str
    body: str
    end: str
    naming: str
    """The sentence naming an unnamed target (empty for most tasks)."""
    closing: str
    """ "thanks" or "thank you" when the request sentence ends with it (it moves after a later correction)."""

    def join(
        self,
        *,
        body: str | None = None,
        naming: str | None = None,
        before: Sequence[str] = (),
        later: Sequence[str] = (),
        after: Sequence[str] = (),
    ) -> str:
        """`before` + request + naming + `later` (corrections: before the closing thanks) + `after`."""
        end, closing = self.end, ""
        if self.closing and later:  # a correction never follows the thanks: the thanks moves after it
            closing = V.CLOSING_SENTENCES[self.closing]
        elif self.closing:
            end = f"{self.end[:-1]}, {self.closing}{self.end[-1]}"
        request = self.prefix + (self.body if body is None else body) + end
        parts = [*before, request, self.naming if naming is None else naming, *later, closing, *after]
        return _tidy(" ".join(p.strip() for p in parts if p.strip()))


def _tidy(text: str) -> str:
    """Punctuation a composition can leave: doubled commas, a comma before a stop, a lowercase sentence start."""
    text = re.sub(r",\s*,", ",", text)
    text = re.sub(r",\s*([.?!])", r"\1", text)
    text = re.sub(r"\s+([,.?!])", r"\1", text)
    text = re.sub(r"\s{2,}", " ", text)
    return re.sub(r"([.?!]\s+)([a-z])", lambda m: m.group(1) + m.group(2).upper(), text).strip()


@dataclass(frozen=True)
class _NP:
    """The target's noun phrase in a segment: [start, end) covers determiner, modifiers, noun and a post-noun."""

    start: int
    end: int
    det: str
    mods: str
    noun: str
    post: str

    @property
    def plural(self) -> bool:
        word = self.noun.split()[-1].lower()
        return word.endswith("s") and not word.endswith("ss")

    @property
    def name(self) -> str:
        return f"the {self.noun}{self.post}"


class RulesV3Generator:
    """Rule-based generator, version 3: same request seed, same utterance, byte for byte."""

    name = "rules"
    prompt_version = V.VERSION

    def __init__(self, candidates: int = DEFAULT_CANDIDATES) -> None:
        if candidates < 1:
            raise ValueError(f"candidates must be a positive number, got {candidates}")
        self.candidates = candidates

    def generate(self, requests: Sequence[GenerationRequest]) -> list[str]:
        """The first candidate of each request (the one drawn with the request's own seed)."""
        return [self.generate_one(r) for r in requests]

    def generate_candidates(self, requests: Sequence[GenerationRequest]) -> list[list[tuple[int, str]]]:
        """(seed, utterance) for K candidates per request; the first uses the request's own seed."""
        out = []
        for request in requests:
            count = 1 if request.pattern == CLEAN else self.candidates
            seeds = [request.seed] + [derive_seed(request.seed, "candidate", k) for k in range(1, count)]
            out.append([(seed, self.generate_one(replace(request, seed=seed))) for seed in seeds])
        return out

    def generate_one(self, request: GenerationRequest) -> str:
        rng = random.Random(request.seed)
        if request.pattern == CLEAN:
            return self.conversationalize(request.task, rng)
        parts = self._parts(request.task, request.clean)
        transform = self._v3_transforms()[request.pattern]
        return transform(request.task, parts, request.level, rng, persona_for(request.task.task_id))

    def _v3_transforms(self) -> dict[str, Callable[[Task, _Parts, int, random.Random, Persona], str]]:
        return {
            "referential_imprecision": self.referential_imprecision,
            "object_substitution": self.object_substitution,
            "empty_speech": self.empty_speech,
            "topic_drift": self.topic_drift,
            "intrusion": self.intrusion,
        }

    # --- step 1 --------------------------------------------------------------------------------------------------
    def conversationalize(self, task: Task, rng: random.Random) -> str:
        """rules-v2's clean control; a seed without its target gets one sentence naming it."""
        # a seed's doubled word ("put a a warm plate") is a typo the speaker would not say
        text = re.sub(r"\b(a|an|the) \1\b", r"\1", clean_control.conversationalize(task, rng), flags=re.IGNORECASE)
        terms = task_terms(task)
        if "target" in terms.seed_roles:
            return text
        target = noun(task.pddl_params.object_target).name
        container = task.pddl_params.mrecep_target
        if container and "container" not in terms.seed_roles:
            naming = rng.choice(V.UNNAMED_TARGET_ON).format(name=target, container=noun(container).name)
        else:
            naming = rng.choice(V.UNNAMED_TARGET).format(name=target)
        return f"{text} {naming}"

    def _parts(self, task: Task, clean: str) -> _Parts:
        split = clean_control.split(task, clean)
        end, naming, closing = split.end, split.closing, ""
        found = _CLOSING.search(end)
        if found:
            end, closing = end[: found.start()] + found.group(2), found.group(1)
        return _Parts(split.prefix, split.body, end, naming, closing)

    # --- shared helpers -------------------------------------------------------------------------------------------
    @staticmethod
    def _fields(persona: Persona, **objects: Noun) -> dict[str, str]:
        fields = persona.fields()
        fields.update({k[:1].upper() + k[1:]: _cap(v) for k, v in list(fields.items())})
        for prefix, obj in objects.items():
            fields.update({f"{prefix}_{k}" if k[0].islower() else f"{prefix.upper()}_{k.lower()}": v
                           for k, v in obj.slots().items()})  # fmt: skip
        return fields

    @staticmethod
    def _locate(task: Task, parts: _Parts) -> tuple[str, _NP] | None:
        """Which segment holds the target's first mention (`body` or `naming`) and its noun phrase."""
        for segment in ("body", "naming"):
            text = getattr(parts, segment)
            found = mentions_of(text, task.pddl_params.object_target)
            if found:
                mention = found[0]
                start, det, mods = noun_phrase(text, mention)
                particle = _STATE_PARTICLE.search(text[:start]) if not det else None
                if particle:  # "a rinsed off egg": the phrase reaches back over the particle
                    det, mods, start = particle.group(1), (particle.group(2) + mods).strip(), particle.start()
                post = _POST_NOUN.match(text[mention.end :])
                tail = post.group(0) if post else ""
                written = text[mention.start : mention.end]
                written = written if written.isupper() else written.lower()
                return segment, _NP(start, mention.end + len(tail), det, mods, written, tail)
        return None

    @staticmethod
    def _with_head(np: _NP, head: str, *, plural: bool, mass: bool = False, keep_the: bool = True) -> str:
        """The target's phrase around another head ("a rinsed off" + "lettuce" -> "some rinsed off lettuce")."""
        det = np.det
        if det.lower() in {"a", "an"} or (not det and not keep_the):
            det = "some" if plural or mass else _article(np.mods or head)
        det = det or "the"
        return " ".join(w for w in (det, np.mods, head) if w)

    @staticmethod
    def _replace(parts: _Parts, segment: str, np: _NP, text: str) -> dict[str, str]:
        old = getattr(parts, segment)
        tail = old[np.end :]
        return {segment: re.sub(r",\s*,", ",", old[: np.start] + text + tail)}  # "laptop, no,, turn" in v2

    def _typed_objects(self, task: Task, pickupable_only: bool = False) -> list[str]:
        pool = set(categories().pickupable) if pickupable_only else None
        return [c for c in clean_control.scene_candidates(task, pool) if kinds_of(c)]

    # --- Referential Imprecision ----------------------------------------------------------------------------------
    def referential_imprecision(self, task: Task, parts: _Parts, level: int, rng: random.Random, who: Persona) -> str:
        """L1 vague word + the name at once; L2 the name after the request; L3 circumlocution, then the name."""
        located = self._locate(task, parts)
        if located is None:
            return parts.join()  # nothing to blur; the verifier records the failure
        segment, np = located
        fields = self._fields(who)
        vague_word = rng.choice(V.VAGUE_PLURAL if np.plural else V.VAGUE_SINGULAR)
        keep = rng.random() < 0.5
        vague = self._with_head(replace(np, det="that" if np.det.lower() == "the" and not keep else np.det), vague_word,
                                plural=np.plural)  # fmt: skip
        name = np.name
        fmt = {**fields, "name": name, "Name": _cap(name), "name_is": "are" if np.plural else "is"}
        if level == 1:
            hesitation = (
                f"{rng.choice(V.HESITATIONS)}, "
                if draw(rng, "referential_imprecision", 1, "hesitations before the name")
                else ""
            )
            changed = self._replace(parts, segment, np, f"{vague}, {hesitation}{name}")
            after = (
                [rng.choice(V.FORGETTING).format(**fmt)]
                if chance(rng, "referential_imprecision", 1, "a short remark on forgetting after the request")
                else []
            )
            return parts.join(**changed, after=after)
        if level == 2:
            changed = self._replace(parts, segment, np, vague)
            later = []
            if draw(rng, "referential_imprecision", 2, "word-search sentences before the name"):
                later.append(rng.choice(V.SEARCH_NAMED).format(**fmt))
            core = rng.choice(V.NAME_CORES).format(**fmt)
            lead = rng.choice(V.NAME_LEADS)
            tag = (
                rng.choice(V.NAME_TAGS)
                if chance(rng, "referential_imprecision", 2, "a tag after the name (of course, dear, ...)")
                else ""
            )
            if tag and tag.strip(", ") in core:
                tag = ""
            later.append(_cap(lead + core + tag) + ".")
            return parts.join(**changed, later=later)
        kinds = sorted(kinds_of(task.pddl_params.object_target) & set(V.DESCRIPTIONS))
        bank = V.DESCRIPTIONS[rng.choice(kinds)] if kinds else V.GENERIC_DESCRIPTIONS
        description = rng.choice(bank).format(**fields)
        if np.plural:
            description = re.sub(r"\bone\b", "ones", description)
        count = draw(rng, "referential_imprecision", 3, "vague references in the request")
        stand_in = [vague, description, rng.choice(V.SECOND_VAGUE)]
        if count == 3:
            extra = rng.choice([v for v in (V.VAGUE_PLURAL if np.plural else V.VAGUE_SINGULAR) if v != vague_word])
            stand_in.insert(1, f"the {extra}")
        changed = self._replace(parts, segment, np, ", ".join(stand_in) + ",")
        search: list[str] = []
        for _ in range(draw(rng, "referential_imprecision", 3, "word-search sentences")):
            if not search or rng.random() < 0.5:
                said = _lead_words(" ".join(search))
                lead = rng.choice([x for x in V.SEARCH_LEADS if not _lead_words(x) & said] or V.SEARCH_LEADS)
                search.append(f"{lead}, {rng.choice(V.SEARCHES)}.")
            else:
                search.append(rng.choice(V.SEARCH_SENTENCES).format(**fmt))
        naming = rng.choice(V.FINAL_NAMINGS).format(**fmt)
        search = [s for i, s in enumerate(search) if s not in search[:i]]
        return parts.join(**changed, later=[*search, naming])

    # --- Object Substitution --------------------------------------------------------------------------------------
    def _competitors(self, task: Task, rng: random.Random, count: int) -> list[str]:
        target = task.pddl_params.object_target
        candidates = self._typed_objects(task, pickupable_only=True)
        same = [c for c in candidates if kinds_of(c) & kinds_of(target)]
        others = [c for c in candidates if c not in same]
        rng.shuffle(same)
        rng.shuffle(others)
        return (same + others)[:count]

    def object_substitution(self, task: Task, parts: _Parts, level: int, rng: random.Random, who: Persona) -> str:
        """L1 a wrong in-scene object corrected at once; L2 corrected after the request; L3 two wrong objects."""
        located = self._locate(task, parts)
        comps = self._competitors(task, rng, 2)
        if located is None or not comps:
            return parts.join()  # nothing to substitute; the verifier records the failure
        segment, np = located
        first, second = noun(comps[0]), noun(comps[-1])
        wrong = self._with_head(np, first.name + np.post, plural=first.plural, mass=first.mass)
        name = np.name
        fmt = {
            **self._fields(who),
            "name": name,
            "Name": _cap(name),
            "name_is": "are" if np.plural else "is",
            "comp": first.the,
            "comp_was": first.was,
            "comp2": second.the,
        }
        if level == 1:
            cue = rng.choice(V.REPAIR_CUES)
            filler = rng.choice(V.REPAIR_FILLERS)
            # the name said twice ("no, the box, the box"): the paper's repetition lowers lexical diversity
            twice = f", {name}" if chance(rng, "object_substitution", 1, "the name said twice") else ""
            changed = self._replace(parts, segment, np, f"{wrong}, {cue}, {filler}{name}{twice}")
            after = (
                [rng.choice(V.SLIP_REMARKS).format(**fmt)]
                if chance(rng, "object_substitution", 1, "a short remark on the slip after the request")
                else []
            )
            return parts.join(**changed, after=after)
        if level == 2:
            changed = self._replace(parts, segment, np, wrong)
            later = []
            for i in range(draw(rng, "object_substitution", 2, "correction sentences")):
                if i == 0:
                    core = rng.choice(V.CORRECTION_CORES).format(**fmt)
                    # a cue in the lead as well: Level 2 repairs a little more than Level 1 (see markers/paper.py)
                    lead = rng.choice([x for x in V.CORRECTION_LEADS if x and REPAIR.search(x)])
                    tag = rng.choice(V.CORRECTION_TAGS)
                    if chance(rng, "object_substitution", 2, "the name said twice") and not core.endswith(name):
                        tag = f", {name}"
                    later.append(_cap(lead + core + (tag if tag.strip(", ") not in core else "")) + ".")
                else:
                    said = " ".join(later)
                    ends = [f"{_cap(name)}.", f"{_cap(name)}, {name}."] + ([] if "yes" in _lead_words(said) else
                                                                         [f"Yes, {name}."])  # fmt: skip
                    later.append(rng.choice(ends))
            return parts.join(**changed, later=later)
        slip = rng.choice(V.SECOND_SLIPS).format(**fmt)
        changed = self._replace(parts, segment, np, f"{wrong}, {slip},")
        core = rng.choice(V.FINAL_CORES).format(**fmt)
        final = _cap(rng.choice(V.FINAL_LEADS) + core + ("" if core.endswith(name) else f", {name}")) + "."
        later = [final]
        if draw(rng, "object_substitution", 3, "correction sentences") == 2:
            remarks = [r for r in V.SLIP_REMARKS if not _lead_words(r) & _lead_words(final)] or list(V.SLIP_REMARKS)
            later.append(
                rng.choice(
                    ([] if "yes" in _lead_words(final) else [f"Yes, {name}."])
                    # not a second sentence opening with the name ("The knife, sorry, ... The knife, that's it.")
                    + [
                        f"That's it, {name}."
                        if final.lower().startswith(name.lower())
                        else f"{_cap(name)}, that's it.",
                        rng.choice(remarks).format(**fmt),
                    ]
                )
            )
        return parts.join(**changed, later=later)

    # --- Empty Speech ---------------------------------------------------------------------------------------------
    @staticmethod
    def _fresh(options: Sequence[str], said: set[str]) -> list[str]:
        """The options sharing no filler word with what the utterance already said ("well, ... oh well" reads as
        a stutter of the generator, not of the speaker); all of them when none is fresh."""

        def overlaps(option: str) -> bool:  # one contains the other, word for word ("well" in "oh well")
            said_words = (u for u in said if u)
            return any(re.search(rf"\b{re.escape(u)}\b", option) or re.search(rf"\b{re.escape(option)}\b", u)
                       for u in said_words)  # fmt: skip

        fresh = [o for o in options if o.strip(", ") and not overlaps(o.strip(", ").lower())]
        return fresh or list(options)

    def _empty_sentence(self, rng: random.Random, said: set[str], plain: bool) -> str:
        lead = rng.choice(self._fresh(V.EMPTY_LEADS, said))
        said.add(lead.lower())
        core = rng.choice(self._fresh(V.EMPTY_CORES_PLAIN if plain else V.EMPTY_CORES, said))
        said.add(core.lower())
        tag = rng.choice(["", *self._fresh(V.EMPTY_TAGS, said)])
        sentence = f"{lead}, {core}{tag}."
        if not EMPTY_SPEECH.search(sentence):  # every empty sentence holds a cue the verifier knows
            tag = f", {rng.choice(self._fresh(V.EMPTY_TAIL_CUES, said))}"
            sentence = f"{lead}, {core}{tag}."
        said.add(tag.strip(", ").lower())
        return sentence

    def empty_speech(self, task: Task, parts: _Parts, level: int, rng: random.Random, who: Persona) -> str:
        """L1 one filler inside the request; L2 two or three, and empty sentences; L3 more, around the request."""
        del who  # empty speech says nothing personal
        body = parts.body
        points = clean_control.insertion_points(task, body)
        inside = draw(rng, "empty_speech", level, "fillers inside the request")
        # mostly discourse markers, sometimes a stock phrase (the paper's empty speech is marker-heavy)
        said: set[str] = set()  # no filler word twice in one utterance
        fillers: list[str] = []
        while len(fillers) < inside:
            pick = rng.choice(self._fresh(V.MARKERS if rng.random() < 0.75 else V.FILLERS, said))
            if pick not in fillers:
                fillers.append(pick)
                said.add(pick.lower())
        clusters = []
        for filler in fillers:
            if rng.random() < {1: 0.5, 2: 0.35, 3: 0.3}[level]:
                partner = rng.choice(self._fresh([p for p in V.FILLER_PARTNERS if p != filler], said))
                said.add(partner.lower())
                filler = f"{partner}, {filler}" if rng.random() < 0.5 else f"{filler}, {partner}"
            clusters.append(filler)
        # distinct boundaries while there are enough, so no more than three fillers stand in a row
        chosen = rng.sample(points, min(inside, len(points)))
        while len(chosen) < inside:
            chosen.append(rng.choice(points))
        stacked: dict[int, list[str]] = {}
        for at, cluster in zip(chosen, clusters, strict=True):
            stacked.setdefault(at, []).append(cluster)
        for at in sorted(stacked, reverse=True):
            words = stacked[at][:3]  # one boundary holds three fillers at most (the checks need three inside)
            while sum(len(c.split(", ")) for c in words) > 3:  # trim partners first, never a counted filler
                longest = max(range(len(words)), key=lambda i: len(words[i].split(", ")))
                pieces = words[longest].split(", ")
                words[longest] = (
                    next(p for p in pieces if EMPTY_SPEECH.search(f", {p},")) if len(pieces) > 1 else pieces[0]
                )
                if all(len(c.split(", ")) == 1 for c in words):
                    break
            body = clean_control.insert(body, at, ", ".join(words))
        count = draw(rng, "empty_speech", level, "empty sentences")
        sentences = [self._empty_sentence(rng, said, level == 3 and rng.random() < 0.7) for _ in range(count)]
        before: list[str] = []
        if level == 3 and sentences and chance(rng, "empty_speech", 3, "an empty sentence before the request"):
            before = [sentences.pop(0)]
        opener = level == 1 and not sentences and rng.random() < 0.4
        text = parts.join(body=body, before=before, after=sentences)
        if opener:  # a discourse marker opens the utterance
            lead = rng.choice(self._fresh(("Well", "Oh", "Um", "So", "Right"), said))
            first = text.split(" ", 1)[0]
            text = f"{lead}, {text if first in {'I', 'I’d'} or first.isupper() else text[:1].lower() + text[1:]}"
        return text

    # --- Topic Drift ----------------------------------------------------------------------------------------------
    def _frame(
        self,
        rng: random.Random,
        bank: Sequence[V.Frame],
        pool: list[str],
        who: Persona,
        task_objects: list[str],
        spent: set[str] | None = None,
    ) -> tuple[str, str] | None:
        """(sentence, scene object) from the first frame (in a random order) that some pool object fits; a frame in
        `spent` (said already in this utterance: "Betty always wanted the plate ... Betty always wanted the
        painting") is skipped, and the chosen one is added to it."""
        spent = set() if spent is None else spent
        for frame in rng.sample(list(bank), len(bank)):
            if (frame.late is not None and frame.late != who.late_spouse) or frame.text in spent:
                continue
            fits = [c for c in pool if "*" in frame.x or kinds_of(c) & frame.x]
            if not fits:
                continue
            objects = {"x": noun(fits[0])}
            if frame.t:
                tied = [t for t in task_objects if "*" in frame.t or kinds_of(t) & frame.t]
                if not tied:
                    continue
                objects["t"] = noun(rng.choice(tied))
            spent.add(frame.text)
            return _cap(frame.text.format(**self._fields(who, **objects))), fits[0]
        return None

    def topic_drift(self, task: Task, parts: _Parts, level: int, rng: random.Random, who: Persona) -> str:
        """L1 a remark on a scene object; L2 on to a memory of the speaker's; L3 through memories to their life."""
        pool = self._typed_objects(task)
        rng.shuffle(pool)
        terms = task_terms(task)
        named = [kind for role, kind in terms.role_types.items() if role in terms.seed_roles or role == "target"]
        # never the destination: "the toilet right by the tissue box" muddles where the thing is to go
        destination = task.pddl_params.parent_target
        task_objects = sorted({k for k in named if kinds_of(k) and k != destination})
        count = draw(rng, "topic_drift", level, "drift sentences")
        objects = draw(rng, "topic_drift", level, "scene objects")
        texts: list[str] = []
        tied = chance(rng, "topic_drift", level, "the remark ties a task object to a scene object")
        stages = [V.NEAR_TIED if tied and task_objects else V.NEAR] + [V.MEMORY] * (objects - 1)
        spent: set[str] = set()
        for bank in stages:
            found = self._frame(rng, bank, pool, who, task_objects, spent) or self._frame(
                rng, V.NEAR, pool, who, [], spent
            )
            if found is None:
                break
            sentence, used = found
            pool.remove(used)
            texts.append(sentence)
        far = list(V.FAR) + list(V.FAR_LATE if who.late_spouse else V.FAR_ALIVE)
        fields = self._fields(who)
        extra = rng.sample(far, len(far))
        while len(texts) < count:
            if level == 1 and task_objects:
                back = noun(rng.choice(task_objects))
                texts.append(_cap(rng.choice(V.ASIDES_TIED).format(**self._fields(who, t=back))))
            elif level == 1:
                texts.append(rng.choice(V.ASIDES))
            else:
                texts.append(_cap(extra.pop().format(**fields)))
        leads = rng.sample(V.DRIFT_LEADS, len(V.DRIFT_LEADS))
        out = []
        for text in texts:
            opener = text.split(",", 1)[0]
            if ("," in text and len(opener.split()) <= 2) or rng.random() < 0.6 or not leads:
                out.append(text)
                continue
            said = " ".join([*out, *texts]).lower()
            lead = leads.pop()
            # "You know, ..., you know": the lead would be said twice
            if re.search(rf"\b{re.escape(lead.strip(', ').lower())}\b", said):
                out.append(text)
                continue
            out.append(_cap(lead + _after_lead(text)))
        # a tag said once: "made one in the shed, you know. I was a librarian for years, you know."
        tagged = [i for i, t in enumerate(out) if re.search(r", you know(?=[.,])", t)]
        for i in tagged[1:]:
            out[i] = re.sub(r", you know(?=[.,])", "", out[i])
        return parts.join(after=out)

    # --- Intrusion ------------------------------------------------------------------------------------------------
    def _resumption(self, rng: random.Random, before: str) -> str:
        used, said = set(openers(f"{before} x")), _lead_words(before)
        fits = [r for r in V.RESUMPTIONS if (openers(f"{r}x") or [""])[0] not in used]
        return rng.choice([r for r in fits if not _lead_words(r) & said] or fits)

    def intrusion(self, task: Task, parts: _Parts, level: int, rng: random.Random, who: Persona) -> str:
        """L1 a short off-task thought mid-request; L2 a longer one; L3 fragments, a restatement, a second thought."""
        fields = self._fields(who)
        body = parts.body
        points = clean_control.insertion_points(task, body)
        span = request_span(task_terms(task), body)
        start = span[0] if span else 0
        # never between a verb and its object ("while holding, oh, ... a book"): right after a task object's
        # name, else (no boundary follows one) not straight after the first word
        ends = {m.end for kind in task_terms(task).task_types for m in mentions_of(body, kind)}
        after_object = [p for p in points if any(0 <= p - e <= 2 for e in ends)]
        # no boundary follows an object inside the request: right after the last object, when words follow it
        last_object = [e for e in sorted(ends) if e > start and body[e:].strip(" ,")][-1:]
        later_points = [p for p in points if len(body[start:p].split()) >= 2]
        at = rng.choice(after_object or last_object or later_points or points)
        head, rest = body[:at].rstrip().rstrip(","), body[at:]

        def thought() -> str:
            return rng.choice(V.THOUGHTS).format(**fields)

        def follow(exclude: Sequence[str] = ()) -> str:
            return rng.choice([f for f in V.FOLLOWS if f not in exclude]).format(**fields)

        if level in (1, 2):
            name = "intrusion sentences"
            count = draw(rng, "intrusion", level, name)
            first = thought()
            comma = chance(
                rng, "intrusion", level, "the intrusion is cut in with a comma (else an ellipsis, a sentence more)"
            )
            opener = rng.choice(("", "oh, ", "oh, ", "hang on, ", "ooh, ")) if comma else ""
            follows: list[str] = []
            while len(follows) < count - 1:  # a follow-up never repeats the opener's "oh"
                follows.append(follow([*follows, *(f for f in V.FOLLOWS if _lead_words(f) & _lead_words(opener))]))
            cut = f"{head}, {opener}{first}" if comma else f"{head}... {_cap(first)}"
            said = " ".join([cut, *follows])
            return parts.join(body=f"{said} {self._resumption(rng, said)}{rest.lstrip(' ,')}")
        fragments: list[str] = []
        wanted = draw(rng, "intrusion", 3, "fragments in the first intrusion")
        for candidate in rng.sample(V.FRAGMENTS, len(V.FRAGMENTS)):
            text = candidate.format(**fields)
            if not set(openers(text)) & set(openers(" ".join(fragments))):
                fragments.append(text)
            if len(fragments) == wanted:
                break
        restated = body[start:at].strip().rstrip(",")
        restated = restated if restated.split(" ", 1)[0].isupper() else restated[:1].lower() + restated[1:]
        fragment_leads = _lead_words(" ".join(fragments))
        restate = rng.choice(
            [r for r in V.RESTATEMENTS if not _lead_words(r) & fragment_leads] or V.RESTATEMENTS
        ).format(restate=restated)
        second = [thought()]
        if draw(rng, "intrusion", 3, "sentences in the second intrusion") == 2:
            second.append(follow())
        said = " ".join([f"{restate}, {second[0]}", *second[1:]])
        resume = self._resumption(rng, " ".join([*fragments, said]))
        return parts.join(body=f"{head}. {' '.join(fragments)} {said} {resume}{rest.lstrip(' ,')}")
