"""The object-space lexicon shared by generation and verification.

Paper, appendix "Rule-Constrained Generation": each seed is associated with an object-space record, the
object types present in its AI2-THOR scene and their lexical aliases. This module holds the aliases (how
people name each type, including the words ALFRED annotators used: "cubby" for a shelf, "bank card" for a
credit card), the state words, the task verbs, and a matcher that finds object mentions in free text.

An alias can name several types ("table" is a dining table, a coffee table, a side table or a desk); a
mention is then grounded in a scene when any of its types is present there.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from functools import cache, lru_cache
from itertools import pairwise

from talkdem.skills import natural_name

__all__ = [
    "ALIASES",
    "DISPLAY_NAMES",
    "STATE_WORDS",
    "TASK_VERBS",
    "Mention",
    "display_name",
    "find_mentions",
    "mentions_of",
    "word_spans",
]

# type -> surface forms (lowercase; the first is the spoken default). Plurals are matched automatically.
ALIASES: dict[str, tuple[str, ...]] = {
    "AlarmClock": ("alarm clock", "clock"),
    "Apple": ("apple",),
    "ArmChair": ("armchair", "arm chair", "chair"),
    "BaseballBat": ("baseball bat", "bat"),
    "BasketBall": ("basketball", "ball"),
    "Bathtub": ("bathtub", "bath", "tub"),
    "BathtubBasin": ("bathtub", "tub", "bath"),
    "Bed": ("bed",),
    "Blinds": ("blinds",),
    "Book": ("book",),
    "Boots": ("boots",),
    "Bowl": ("bowl",),
    "Box": ("box", "carton", "cardboard box"),
    "Bread": ("bread", "loaf of bread", "loaf", "bread loaf"),
    "ButterKnife": ("butter knife",),
    "CD": ("cd", "disc", "compact disc"),
    "Cabinet": ("cabinet", "cupboard"),
    "Candle": ("candle",),
    "Cart": ("cart",),
    "CellPhone": ("cell phone", "phone", "cellphone", "mobile phone"),
    "Chair": ("chair",),
    "Cloth": ("cloth", "rag"),
    "CoffeeMachine": ("coffee maker", "coffee machine"),
    "CoffeeTable": ("coffee table", "table", "center table"),
    "CounterTop": ("counter", "counter top", "countertop", "kitchen counter", "kitchen island", "island"),
    "CreditCard": ("credit card", "bank card", "card"),
    "Cup": ("cup", "goblet"),
    "Curtains": ("curtains",),
    "Desk": ("desk", "computer desk", "table"),
    "DeskLamp": ("desk lamp", "lamp", "table lamp", "light"),
    "DiningTable": ("dining table", "table", "kitchen table"),
    "DishSponge": ("sponge", "dish sponge"),
    "Drawer": ("drawer",),
    "Dresser": ("dresser", "chest of drawers"),
    "Egg": ("egg",),
    "Faucet": ("faucet", "tap"),
    "FloorLamp": ("floor lamp", "lamp", "standing lamp", "light"),
    "Footstool": ("footstool",),
    "Fork": ("fork",),
    "Fridge": ("fridge", "refrigerator"),
    "GarbageCan": (
        "garbage can",
        "trash can",
        "trashcan",
        "bin",
        "garbage bin",
        "trash bin",
        "waste basket",
        "wastebasket",
        "waste bin",
        "recycling bin",
        "recycle bin",
        "trash",
        "garbage",
    ),
    "Glassbottle": ("glass bottle",),
    "HandTowel": ("hand towel", "towel"),
    "HandTowelHolder": ("towel holder", "towel rail"),
    "HousePlant": ("house plant", "plant", "houseplant"),
    "Kettle": ("kettle", "tea kettle"),
    "KeyChain": ("keys", "key chain", "keychain", "key"),
    "Knife": ("knife",),
    "Ladle": ("ladle",),
    "Lamp": ("lamp",),
    "Laptop": ("laptop", "computer"),
    "LaundryHamper": ("laundry hamper", "hamper", "laundry basket"),
    "LaundryHamperLid": ("hamper lid",),
    "Lettuce": ("lettuce", "head of lettuce", "cabbage"),
    "LightSwitch": ("light switch",),
    "Microwave": ("microwave",),
    "Mirror": ("mirror",),
    "Mug": ("mug", "coffee mug"),
    "Newspaper": ("newspaper", "paper"),
    "Ottoman": ("ottoman",),
    "Painting": ("painting", "picture on the wall"),
    "Pan": ("pan", "frying pan", "fry pan", "skillet"),
    "PaperTowelRoll": ("paper towel roll", "paper towels"),
    "Pen": ("pen",),
    "Pencil": ("pencil",),
    "PepperShaker": ("pepper shaker", "pepper"),
    "Pillow": ("pillow", "cushion"),
    "Plate": ("plate", "tray", "pie plate"),
    "Plunger": ("plunger",),
    "Poster": ("poster",),
    "Pot": ("pot", "cooking pot"),
    "Potato": ("potato",),
    "RemoteControl": ("remote control", "remote", "tv remote"),
    "Safe": ("safe",),
    "SaltShaker": ("salt shaker", "salt"),
    "ScrubBrush": ("scrub brush",),
    "Shelf": ("shelf", "cubby", "shelves"),
    "ShowerCurtain": ("shower curtain",),
    "ShowerDoor": ("shower door",),
    "ShowerGlass": ("shower glass",),
    "ShowerHead": ("shower head", "showerhead"),
    "SideTable": ("side table", "end table", "night stand", "nightstand", "table", "bedside table"),
    "Sink": ("sink",),
    "SinkBasin": ("sink", "sink basin", "kitchen sink", "basin"),
    "SoapBar": ("soap", "bar of soap", "bar soap", "soap bar"),
    "SoapBottle": ("soap dispenser", "soap bottle", "soap"),
    "Sofa": ("sofa", "couch"),
    "Spatula": ("spatula",),
    "Spoon": ("spoon",),
    "SprayBottle": ("spray bottle",),
    "Statue": ("statue", "figurine"),
    "StoveBurner": ("stove", "stovetop", "burner", "stove burner"),
    "StoveKnob": ("stove knob",),
    "TVStand": ("tv stand", "entertainment center"),
    "TeddyBear": ("teddy bear", "teddy"),
    "Television": ("television", "tv"),
    "TennisRacket": ("tennis racket", "racket"),
    "TissueBox": ("tissue box", "tissues", "tissue", "box of tissues"),
    "Toaster": ("toaster",),
    "Toilet": ("toilet", "toilet tank", "water tank"),
    "ToiletPaper": ("toilet paper", "toilet roll", "roll of toilet paper"),
    "ToiletPaperHanger": ("toilet paper holder", "holder", "toilet roll holder"),
    "Tomato": ("tomato",),
    "Towel": ("towel", "bath towel"),
    "TowelHolder": ("towel rack", "towel holder"),
    "Vase": ("vase",),
    "Watch": ("watch", "wristwatch"),
    "WateringCan": ("watering can", "water pot"),
    "Window": ("window",),
    "WineBottle": ("wine bottle", "wine", "bottle of wine"),
}

# Spoken names for types whose first alias is not the natural phrase.
DISPLAY_NAMES: dict[str, str] = {"CD": "CD", "TVStand": "TV stand", "Television": "TV"}

# State expressions ALFRED annotators use for the three state-changing task types and for slicing.
STATE_WORDS: dict[str, tuple[str, ...]] = {
    "heat": ("hot", "heated", "heat", "warm", "warmed", "warming", "cooked", "cook", "microwaved", "microwave"),
    "cool": ("cold", "chilled", "chill", "cooled", "cool", "refrigerated", "refrigerate"),
    "clean": ("clean", "cleaned", "cleanly", "washed", "wash", "rinsed", "rinse", "wet"),
    "slice": ("sliced", "slice", "slices"),
}

# Task verbs (lemma -> inflected forms). The verifier requires every task verb of the seed to survive.
TASK_VERBS: dict[str, tuple[str, ...]] = {
    "put": ("put", "puts", "putting"),
    "place": ("place", "places", "placed", "placing"),
    "move": ("move", "moves", "moving"),
    "set": ("set", "sets", "setting"),
    "carry": ("carry", "carries", "carrying"),
    "take": ("take", "takes", "taking"),
    "bring": ("bring", "brings", "bringing"),
    "throw": ("throw", "throws", "throwing"),
    "examine": ("examine", "examines", "examining"),
    "inspect": ("inspect", "inspects", "inspecting"),
    "look": ("look", "looks", "looking"),
    "see": ("see", "sees", "seeing"),
    "pick": ("pick", "picks", "picking"),
    "grab": ("grab", "grabs", "grabbing"),
    "get": ("get", "gets", "getting"),
    "retrieve": ("retrieve", "retrieves", "retrieving"),
    "turn": ("turn", "turns", "turning"),
    "hold": ("hold", "holds", "holding"),
    "dispose": ("dispose", "disposes", "disposing"),
    "remove": ("remove", "removes", "removing"),
    "return": ("return", "returns", "returning"),
    "replace": ("replace", "replaces", "replacing"),
}

_WORD = re.compile(r"[a-z0-9]+(?:'[a-z]+)?")


@dataclass(frozen=True)
class Mention:
    """One object mention: the matched surface form, its character span and the types it can name."""

    alias: str
    start: int
    end: int
    types: frozenset[str]


@cache
def _alias_types() -> dict[str, frozenset[str]]:
    table: dict[str, set[str]] = {}
    for object_type, aliases in ALIASES.items():
        for alias in aliases:
            table.setdefault(alias, set()).add(object_type)
    return {alias: frozenset(types) for alias, types in table.items()}


_MAX_ALIAS_WORDS = max(len(alias.split()) for aliases in ALIASES.values() for alias in aliases)


def find_mentions(text: str) -> list[Mention]:
    """Every object mention in `text`, left to right, longest alias first at each position."""
    return list(_find_mentions(text))


@cache
def _first_words() -> frozenset[str]:
    return frozenset(alias.split()[0] for alias in _alias_types())


@lru_cache(maxsize=65536)
def _find_mentions(text: str) -> tuple[Mention, ...]:
    table = _alias_types()
    firsts = _first_words()
    matches = list(_WORD.finditer(text.lower()))
    words = [m.group(0) for m in matches]
    joined = [not text[a.end() : b.start()].strip() for a, b in pairwise(matches)]
    found = []
    i = 0
    while i < len(words):
        word = words[i]
        if word not in firsts and word[:-1] not in firsts and word[:-2] not in firsts:
            i += 1
            continue
        for n in range(min(_MAX_ALIAS_WORDS, len(words) - i), 0, -1):
            if not all(joined[i : i + n - 1]):
                continue  # aliases never cross punctuation
            alias = _singular(" ".join(words[i : i + n]), table)
            if alias is not None:
                found.append(Mention(alias, matches[i].start(), matches[i + n - 1].end(), table[alias]))
                i += n
                break
        else:
            i += 1
    return tuple(found)


def _singular(phrase: str, table: dict[str, frozenset[str]]) -> str | None:
    if phrase in table:
        return phrase
    for suffix in ("s", "es"):
        if phrase.endswith(suffix) and phrase[: -len(suffix)] in table:
            return phrase[: -len(suffix)]
    return None


def mentions_of(text: str, object_type: str) -> list[Mention]:
    """The mentions that can name `object_type`."""
    return [m for m in find_mentions(text) if object_type in m.types]


def display_name(object_type: str) -> str:
    """How the generator names a type aloud: `KeyChain` -> `keys`, `CounterTop` -> `counter`."""
    if object_type in DISPLAY_NAMES:
        return DISPLAY_NAMES[object_type]
    aliases = ALIASES.get(object_type)
    return aliases[0] if aliases else natural_name(object_type)


def word_spans(text: str) -> list[tuple[str, int, int]]:
    """Lowercased words with their character spans (apostrophes kept inside words)."""
    return [(m.group(0), m.start(), m.end()) for m in _WORD.finditer(text.lower())]
