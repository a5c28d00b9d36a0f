"""ALFRED's object categories and their natural-language names, loaded from `categories.json`."""

from __future__ import annotations

import json
import re
from dataclasses import dataclass
from functools import cache
from pathlib import Path

__all__ = ["ObjectCategories", "categories", "indefinite_article", "natural_name", "type_from_natural"]

_CAMEL_BOUNDARY = re.compile(r"(?<=[a-z])(?=[A-Z])")


@dataclass(frozen=True)
class ObjectCategories:
    """Object types by affordance, as ALFRED's skill set enumerates them."""

    findable: tuple[str, ...]
    """Every type a `find` skill can name (80)."""
    pickupable: tuple[str, ...]
    """Types with `pick up` / `put down` skills (53)."""
    openable: tuple[str, ...]
    """Types with `open` / `close` skills (7)."""
    sliceable: tuple[str, ...]
    """Types with a `slice` skill (5)."""
    toggleable: tuple[str, ...]
    """Types with `turn on` / `turn off` skills (4)."""
    receptacle: tuple[str, ...]
    """Types that can hold objects (31)."""


@cache
def categories() -> ObjectCategories:
    raw = json.loads((Path(__file__).parent / "categories.json").read_text())
    return ObjectCategories(**{field: tuple(raw[field]) for field in ObjectCategories.__dataclass_fields__})


def natural_name(object_type: str) -> str:
    """`DeskLamp` -> `desk lamp`; acronyms such as `CD` keep their case."""
    if object_type.isupper():
        return object_type
    return _CAMEL_BOUNDARY.sub(" ", object_type).lower()


@cache
def _natural_to_type() -> dict[str, str]:
    cats = categories()
    every_type = set(cats.findable) | set(cats.receptacle)
    return {natural_name(t).lower(): t for t in every_type}


def type_from_natural(name: str) -> str | None:
    """`desk lamp` -> `DeskLamp` for the vocabulary's types (case-insensitive); None if unknown."""
    return _natural_to_type().get(" ".join(name.lower().split()))


def indefinite_article(name: str) -> str:
    """The article LoTa-Bench's skill set uses: `an` before a written vowel, else `a`."""
    return "an" if name[:1].lower() in "aeiou" else "a"
