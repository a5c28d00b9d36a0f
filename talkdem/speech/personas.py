"""The speakers of `rules-v3`: one per task, composed from banks of biographical parts.

A persona is drawn from the task id alone, so the same person speaks in all 16 instructions of a task (their
drift and intrusions name the same husband, the same grandson, the same old job) and another task gets
another person. Every part is drawn on its own from its bank, so the 300 tasks get about 300 different
biographies from a few dozen entries per bank.
"""

from __future__ import annotations

import hashlib
import random
from dataclasses import dataclass
from functools import cache

__all__ = ["Persona", "Relative", "Work", "persona_for"]


@dataclass(frozen=True)
class Relative:
    """Someone the speaker talks about: "my daughter Susan" (she)."""

    relation: str
    name: str
    he: str
    """Subject pronoun: he or she."""

    @property
    def him(self) -> str:
        return "him" if self.he == "he" else "her"

    @property
    def his(self) -> str:
        return "his" if self.he == "he" else "her"

    @property
    def my(self) -> str:
        """ "my daughter Susan"."""
        return f"my {self.relation} {self.name}"


@dataclass(frozen=True)
class Work:
    """The speaker's old job: what they were and where."""

    was: str
    """ "I was a nurse" -> "a nurse"."""
    place: str
    """Where it happened, after "at" or "in": "the hospital"."""
    colleague: str
    """A workmate's name."""
    detail: str
    """A full sentence about the job, in the past."""


@dataclass(frozen=True)
class Persona:
    """One speaker: household, relatives, former work, places and habits."""

    key: str
    spouse: Relative
    late_spouse: bool
    """True when the spouse has died (the speaker then talks of them in the past)."""
    child: Relative
    other_child: Relative
    grandchild: Relative
    sibling: Relative
    friend: Relative
    work: Work
    hometown: str
    holiday: str
    """Where the family went on holiday: "the caravan at Filey"."""
    habit: str
    """What the speaker does most days: "the crossword"."""
    pet: str
    """ "our old dog Biscuit"."""
    street: str

    def fields(self) -> dict[str, str]:
        """Format fields of a frame: {spouse} "my husband Frank", {Spouse_name} "Frank", {he} "he", ..."""
        out: dict[str, str] = {}
        for label, rel in (
            ("spouse", self.spouse),
            ("child", self.child),
            ("child2", self.other_child),
            ("grandchild", self.grandchild),
            ("sibling", self.sibling),
            ("friend", self.friend),
        ):
            out[label] = rel.my
            out[f"{label}_name"] = rel.name
            out[f"{label}_rel"] = rel.relation
            out[f"{label}_he"] = rel.he
            out[f"{label}_him"] = rel.him
            out[f"{label}_his"] = rel.his
        out.update(
            job=self.work.was,
            workplace=self.work.place,
            colleague=self.work.colleague,
            job_detail=self.work.detail,
            hometown=self.hometown,
            holiday=self.holiday,
            habit=self.habit,
            pet=self.pet,
            street=self.street,
        )
        return out

    def names(self) -> frozenset[str]:
        """Every person's name this speaker uses (what a consistency check looks for)."""
        people = (self.spouse, self.child, self.other_child, self.grandchild, self.sibling, self.friend)
        return frozenset({p.name for p in people} | {self.work.colleague})


_HUSBANDS = ("Frank", "Harold", "Ron", "Dennis", "Alan", "Geoff", "Ken", "Stan", "Walter", "Brian", "Roy", "Eric")
_WIVES = ("Margaret", "Joan", "Barbara", "Doreen", "Irene", "Pat", "Sheila", "Maureen", "Jean", "Audrey", "Vera")
_SONS = ("David", "Michael", "Peter", "Paul", "Stephen", "Graham", "Martin", "Colin", "Keith", "Tony", "Neil")
_DAUGHTERS = ("Susan", "Linda", "Carol", "Janet", "Karen", "Helen", "Julie", "Wendy", "Gillian", "Anne", "Lorraine")
_GRANDSONS = ("Jimmy", "Tom", "Ollie", "Jack", "Harry", "Ben", "Sam", "Josh", "Alfie", "Danny")
_GRANDDAUGHTERS = ("Emily", "Sophie", "Chloe", "Lucy", "Megan", "Ellie", "Amy", "Grace", "Katie", "Holly")
_BROTHERS = ("Ted", "Bill", "Arthur", "Jim", "Norman", "Len", "Cyril", "Fred")
_SISTERS = ("Edna", "Dot", "Elsie", "Mabel", "Nancy", "Rita", "Betty", "Winnie")
_FRIENDS = (
    ("Mrs Patel", "she"),
    ("Mr Hughes", "he"),
    ("Brenda next door", "she"),
    ("Mrs Kowalski", "she"),
    ("Gordon across the road", "he"),
    ("Mrs O'Brien", "she"),
    ("Shirley from church", "she"),
    ("Mr Okafor", "he"),
    ("Hilda two doors down", "she"),
    ("Derek from the darts club", "he"),
    ("Mrs Campbell", "she"),
    ("Fatima from the library", "she"),
)
_WORKS = (
    Work("a nurse", "the hospital", "Sister Murphy", "I did nights on the children's ward for years."),
    Work("a teacher", "the primary school", "Mr Bryce", "I taught the infants to read, forty of them at a time."),
    Work("a postman", "the sorting office", "Reg Gould", "I was out on my round before dawn."),
    Work("a baker", "the bakery on the high street", "Mrs Lowe", "We had the ovens going by four every morning."),
    Work("a signalman", "the railway", "Tommy Reid", "I worked the signals at the junction for thirty years."),
    Work("a seamstress", "the clothing factory", "Ivy", "I sewed collars all day, hundreds of them."),
    Work(
        "a librarian", "the town library", "Miss Hart", "I stamped every library ticket in that town, I should think."
    ),
    Work("a bus conductor", "the depot", "Charlie Mason", "I knew every stop on the number nine by heart."),
    Work("a typist", "the solicitor's office", "Mr Fairbrother", "I could type faster than anyone on the floor."),
    Work("a farmer's wife", "the farm", "old Mr Dunn", "We were up with the cows whatever the weather."),
    Work("a shopkeeper", "our corner shop", "Mrs Ali", "We sold everything from firewood to birthday balloons."),
    Work("a mechanic", "the garage", "Big Steve", "I had my head under a bonnet most of my life."),
    Work("a dinner lady", "the school kitchen", "Pauline", "I served four hundred dinners a day at that school."),
    Work("a miner", "the pit", "Taffy Evans", "I went down the pit at fifteen, like my father."),
    Work("a hairdresser", "the salon", "Glenda", "I did perms for half the women in the street."),
    Work("a bank clerk", "the bank", "Mr Pritchard", "I counted other people's money all day long."),
)
_HOMETOWNS = (
    "Whitby", "Rhyl", "Barnsley", "Paisley", "Wigan", "Swansea", "Cork", "Grimsby", "Stoke", "Hull",
    "Dundee", "Margate", "Bolton", "Derby", "Newry", "Falmouth",
)  # fmt: skip
_HOLIDAYS = (
    "the caravan at Filey",
    "the chalet at Skegness",
    "my aunt's guest house in Llandudno",
    "the holiday camp at Butlins",
    "the beach at Tenby",
    "the little cottage in the Lakes",
    "the boarding house at Blackpool",
    "the campsite near Bude",
    "the hotel in Torquay",
    "the farm in Devon",
    "the seaside at Scarborough",
    "the cabin on Loch Lomond",
)
_HABITS = (
    "the crossword",
    "my knitting",
    "the allotment",
    "choir practice",
    "the darts club",
    "my jigsaws",
    "the racing on the telly",
    "my little walk to the shop",
    "the bird feeder",
    "my letters",
    "the quiz on the radio",
    "bingo on a Friday",
    "my sudoku",
    "the roses",
)
_PETS = (
    "our old dog Biscuit",
    "our cat Sooty",
    "our budgie Joey",
    "our dog Patch",
    "our cat Tiddles",
    "our old dog Rex",
    "Speedy the tortoise",
    "our collie Lassie",
    "Ginger the cat",
    "our terrier Scamp",
)
_STREETS = (
    "Albert Road", "Mill Lane", "Station Street", "Park Terrace", "Church Walk", "Victoria Avenue",
    "Chapel Row", "Queen Street", "Oak Close", "Rose Hill", "Canal Street", "Market Square",
)  # fmt: skip


def _rng(task_id: str, part: str) -> random.Random:
    digest = hashlib.sha256(f"persona:{task_id}:{part}".encode()).digest()
    return random.Random(int.from_bytes(digest[:8], "big"))


def _relative(rng: random.Random, male: tuple[str, ...], female: tuple[str, ...], rel: tuple[str, str]) -> Relative:
    if rng.random() < 0.5:
        return Relative(rel[0], rng.choice(male), "he")
    return Relative(rel[1], rng.choice(female), "she")


@cache
def persona_for(task_id: str) -> Persona:
    """The speaker of one task (the same for all of its instructions, whatever the build seed)."""
    spouse = _relative(_rng(task_id, "spouse"), _HUSBANDS, _WIVES, ("husband", "wife"))
    child_rng = _rng(task_id, "child")
    child = _relative(child_rng, _SONS, _DAUGHTERS, ("son", "daughter"))
    other = child
    while other.name == child.name:  # two children of one name would read as one
        other = _relative(child_rng, _SONS, _DAUGHTERS, ("son", "daughter"))
    grandchild = _relative(_rng(task_id, "grandchild"), _GRANDSONS, _GRANDDAUGHTERS, ("grandson", "granddaughter"))
    sibling = _relative(_rng(task_id, "sibling"), _BROTHERS, _SISTERS, ("brother", "sister"))
    friend_name, friend_he = _rng(task_id, "friend").choice(_FRIENDS)
    return Persona(
        key=task_id,
        spouse=spouse,
        late_spouse=_rng(task_id, "late").random() < 0.5,
        child=child,
        other_child=other,
        grandchild=grandchild,
        sibling=sibling,
        friend=Relative("friend", friend_name, friend_he),
        work=_rng(task_id, "work").choice(_WORKS),
        hometown=_rng(task_id, "hometown").choice(_HOMETOWNS),
        holiday=_rng(task_id, "holiday").choice(_HOLIDAYS),
        habit=_rng(task_id, "habit").choice(_HABITS),
        pet=_rng(task_id, "pet").choice(_PETS),
        street=_rng(task_id, "street").choice(_STREETS),
    )
