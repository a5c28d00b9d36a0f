"""The planner's action space: 214 natural-language skills over ALFRED's object categories."""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum
from functools import cache

from talkdem.skills.categories import categories, indefinite_article, natural_name

__all__ = ["Skill", "SkillVerb", "skill_texts", "vocabulary"]


class SkillVerb(StrEnum):
    """The kinds of skill; each maps to one AI2-THOR interaction (or navigation for `find`)."""

    DONE = "done"
    FIND = "find"
    PICK_UP = "pick up"
    PUT_DOWN = "put down"
    OPEN = "open"
    CLOSE = "close"
    SLICE = "slice"
    TURN_ON = "turn on"
    TURN_OFF = "turn off"


@dataclass(frozen=True, order=True)
class Skill:
    """One skill: a verb and the AI2-THOR object type it names (empty for `done`)."""

    verb: SkillVerb
    object_type: str = ""

    @property
    def text(self) -> str:
        """The canonical string a planner emits, e.g. `find an apple`, `pick up the desk lamp`."""
        if self.verb is SkillVerb.DONE:
            return "done"
        name = natural_name(self.object_type)
        if self.verb is SkillVerb.FIND:
            return f"find {indefinite_article(name)} {name}"
        return f"{self.verb.value} the {name}"

    def __str__(self) -> str:
        return self.text


@cache
def vocabulary() -> tuple[Skill, ...]:
    """All skills, in LoTa-Bench's order: done, find, pick up/put down, open/close, slice, turn on/off."""
    cats = categories()
    skills: list[Skill] = [Skill(SkillVerb.DONE)]
    skills += [Skill(SkillVerb.FIND, t) for t in cats.findable]
    for t in cats.pickupable:
        skills += [Skill(SkillVerb.PICK_UP, t), Skill(SkillVerb.PUT_DOWN, t)]
    for t in cats.openable:
        skills += [Skill(SkillVerb.OPEN, t), Skill(SkillVerb.CLOSE, t)]
    skills += [Skill(SkillVerb.SLICE, t) for t in cats.sliceable]
    for t in cats.toggleable:
        skills += [Skill(SkillVerb.TURN_ON, t), Skill(SkillVerb.TURN_OFF, t)]
    return tuple(skills)


@cache
def skill_texts() -> frozenset[str]:
    """The canonical strings of every vocabulary skill."""
    return frozenset(skill.text for skill in vocabulary())
