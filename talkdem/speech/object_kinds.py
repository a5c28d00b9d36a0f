"""A typed lexicon of the AI2-THOR object types: what kind of thing each one is, and how its name inflects.

The `rules-v3` frames that bring an object into a memory or an association declare the kinds they can take
("bought {a} at the market" takes a keepsake or a dish, never a window or a butter knife), and draw only scene
objects of those kinds. Kinds are about what people do with and say about a thing, not about the simulator's
affordances: a teapot and a vase are both `keepsake`s someone may have been given; a fridge is an `appliance`
that hums and breaks down. A type may have several kinds.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

from talkdem.speech.lexicon import display_name

__all__ = ["KINDS", "OBJECT_KINDS", "Noun", "kinds_of", "noun"]

KINDS: dict[str, str] = {
    "food": "something to eat (fruit, vegetables, bread, eggs)",
    "produce": "food that grows in a garden (apple, tomato, potato, lettuce)",
    "cutlery": "a knife, fork, spoon or kitchen tool held in the hand",
    "crockery": "a cup, mug, bowl or plate",
    "cookware": "a pan, pot or kettle",
    "keepsake": "an ornament or object one is given, keeps and remembers (vase, statue, candle, clock, teddy)",
    "gadget": "a small device (phone, remote, laptop, alarm clock, watch, CD)",
    "pocket": "a small thing carried about and mislaid (keys, card, pen, pencil, phone, watch, glasses)",
    "reading": "a book or newspaper",
    "textile": "cloth, towels, cushions, curtains",
    "toiletry": "soap, toilet paper, tissues, sponges, spray",
    "cleaning": "a cleaning tool (plunger, scrub brush)",
    "bottle": "a bottle or shaker",
    "sport": "a bat, ball or racket",
    "plant": "a plant",
    "picture": "something hung on a wall (painting, poster, mirror)",
    "seat": "something sat on (sofa, armchair, chair, footstool, ottoman)",
    "table": "a table or desk",
    "storage": "a cupboard, drawer, dresser, shelf, box, safe or cart",
    "appliance": "a machine plugged in at home (fridge, microwave, toaster, coffee maker, TV, stove)",
    "lamp": "a lamp",
    "fixture": "part of the house (window, sink, bath, toilet, counter, towel rail, blinds)",
    "bin": "a bin or hamper",
    "footwear": "boots",
}
"""Kind -> what it covers (shown with the frames that use it)."""

OBJECT_KINDS: dict[str, frozenset[str]] = {
    name: frozenset(kinds)
    for name, kinds in {
        "AlarmClock": {"gadget", "keepsake"},
        "Apple": {"food", "produce"},
        "ArmChair": {"seat"},
        "BaseballBat": {"sport"},
        "BasketBall": {"sport"},
        "Bathtub": {"fixture"},
        "BathtubBasin": {"fixture"},
        "Bed": {"seat"},
        "Blinds": {"fixture"},
        "Book": {"reading", "pocket"},
        "Boots": {"footwear"},
        "Bowl": {"crockery"},
        "Box": {"storage"},
        "Bread": {"food"},
        "ButterKnife": {"cutlery"},
        "CD": {"gadget"},
        "Cabinet": {"storage"},
        "Candle": {"keepsake"},
        "Cart": {"storage"},
        "CellPhone": {"gadget", "pocket"},
        "Chair": {"seat"},
        "Cloth": {"textile"},
        "CoffeeMachine": {"appliance"},
        "CoffeeTable": {"table"},
        "CounterTop": {"fixture"},
        "CreditCard": {"pocket"},
        "Cup": {"crockery"},
        "Curtains": {"textile", "fixture"},
        "Desk": {"table"},
        "DeskLamp": {"lamp"},
        "DiningTable": {"table"},
        "DishSponge": {"toiletry"},
        "Drawer": {"storage"},
        "Dresser": {"storage"},
        "Egg": {"food"},
        "Faucet": {"fixture"},
        "FloorLamp": {"lamp"},
        "Footstool": {"seat"},
        "Fork": {"cutlery"},
        "Fridge": {"appliance"},
        "GarbageCan": {"bin"},
        "Glassbottle": {"bottle"},
        "HandTowel": {"textile"},
        "HandTowelHolder": {"fixture"},
        "HousePlant": {"plant"},
        "Kettle": {"cookware", "appliance"},
        "KeyChain": {"pocket"},
        "Knife": {"cutlery"},
        "Ladle": {"cutlery"},
        "Lamp": {"lamp"},
        "Laptop": {"gadget"},
        "LaundryHamper": {"bin"},
        "Lettuce": {"food", "produce"},
        "Microwave": {"appliance"},
        "Mirror": {"picture"},
        "Mug": {"crockery", "keepsake"},
        "Newspaper": {"reading"},
        "Ottoman": {"seat"},
        "Painting": {"picture", "keepsake"},
        "Pan": {"cookware"},
        "PaperTowelRoll": {"toiletry"},
        "Pen": {"pocket"},
        "Pencil": {"pocket"},
        "PepperShaker": {"bottle"},
        "Pillow": {"textile"},
        "Plate": {"crockery"},
        "Plunger": {"cleaning"},
        "Poster": {"picture"},
        "Pot": {"cookware"},
        "Potato": {"food", "produce"},
        "RemoteControl": {"gadget", "pocket"},
        "Safe": {"storage"},
        "SaltShaker": {"bottle"},
        "ScrubBrush": {"cleaning"},
        "Shelf": {"storage"},
        "ShowerCurtain": {"fixture"},
        "ShowerDoor": {"fixture"},
        "SideTable": {"table"},
        "SinkBasin": {"fixture"},
        "SoapBar": {"toiletry"},
        "SoapBottle": {"toiletry", "bottle"},
        "Sofa": {"seat"},
        "Spatula": {"cutlery"},
        "Spoon": {"cutlery"},
        "SprayBottle": {"toiletry", "bottle"},
        "Statue": {"keepsake"},
        "StoveBurner": {"appliance"},
        "TVStand": {"storage"},
        "TeddyBear": {"keepsake", "textile"},
        "Television": {"appliance"},
        "TennisRacket": {"sport"},
        "TissueBox": {"toiletry"},
        "Toaster": {"appliance"},
        "Toilet": {"fixture"},
        "ToiletPaper": {"toiletry"},
        "ToiletPaperHanger": {"fixture"},
        "Tomato": {"food", "produce"},
        "Towel": {"textile"},
        "TowelHolder": {"fixture"},
        "Vase": {"keepsake"},
        "Watch": {"pocket", "keepsake", "gadget"},
        "WateringCan": {"plant"},
        "Window": {"fixture"},
        "WineBottle": {"bottle"},
    }.items()
}
"""AI2-THOR type -> its kinds. Types missing here (switches, knobs, shower heads) are never brought in."""

# Names said without "a": plurals and mass nouns ("some keys", "some bread").
_PLURAL = frozenset({"KeyChain", "Blinds", "Boots", "Curtains"})
_MASS = frozenset({"Bread", "Lettuce", "ToiletPaper", "SoapBar"})


@dataclass(frozen=True)
class Noun:
    """A type's spoken name with the words that agree with it."""

    object_type: str
    name: str
    plural: bool
    mass: bool

    @property
    def the(self) -> str:
        return f"the {self.name}"

    @property
    def a(self) -> str:
        if self.plural or self.mass:
            return f"some {self.name}"
        return f"{'an' if self.name[:1].lower() in 'aeiou' else 'a'} {self.name}"

    @property
    def that(self) -> str:
        return f"{'those' if self.plural else 'that'} {self.name}"

    @property
    def this(self) -> str:
        return f"{'these' if self.plural else 'this'} {self.name}"

    @property
    def it(self) -> str:
        return "them" if self.plural else "it"

    @property
    def its(self) -> str:
        return "their" if self.plural else "its"

    @property
    def is_(self) -> str:
        return "are" if self.plural else "is"

    @property
    def was(self) -> str:
        return "were" if self.plural else "was"

    @property
    def has(self) -> str:
        return "have" if self.plural else "has"

    @property
    def one(self) -> str:
        """What stands for it in "one just like it": "one", or "some" for plurals and mass nouns."""
        return "some" if self.plural or self.mass else "one"

    def slots(self) -> dict[str, str]:
        """Format fields of a frame: {the} {a} {that} {this} {it} {its} {is} {was} {has} {one}, and capitalised."""
        words = {
            "the": self.the,
            "a": self.a,
            "that": self.that,
            "this": self.this,
            "it": self.it,
            "its": self.its,
            "is": self.is_,
            "was": self.was,
            "has": self.has,
            "one": self.one,
            "name": self.name,
        }
        return {**words, **{k.capitalize(): v[:1].upper() + v[1:] for k, v in words.items()}}


@cache
def noun(object_type: str) -> Noun:
    return Noun(object_type, display_name(object_type), object_type in _PLURAL, object_type in _MASS)


def kinds_of(object_type: str) -> frozenset[str]:
    return OBJECT_KINDS.get(object_type, frozenset())
