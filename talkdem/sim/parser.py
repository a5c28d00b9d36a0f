"""Parse a planner's skill string into a vocabulary `Skill`, tolerating case, article and punctuation variants."""

from __future__ import annotations

import re
from functools import cache, lru_cache

from talkdem.skills import Skill, SkillVerb, type_from_natural, vocabulary

__all__ = ["canonical_text", "parse_skill"]

_PATTERN = re.compile(
    r"^(?P<verb>find|pick up|put down|open|close|slice|turn on|turn off)\s+(?:(?:the|an|a)\s+)?(?P<name>.+)$"
)


@cache
def _vocabulary() -> frozenset[Skill]:
    return frozenset(vocabulary())


def parse_skill(text: str) -> Skill | None:
    """`Find an Apple.` -> Skill(FIND, 'Apple'); None for anything outside the 214-skill vocabulary."""
    if not isinstance(text, str):
        return None
    return _parse(text)


@lru_cache(maxsize=8192)  # planners repeat the same few hundred strings across thousands of episodes
def _parse(text: str) -> Skill | None:
    normalised = " ".join(text.strip().rstrip(".!").split()).lower()
    if normalised == "done":
        return Skill(SkillVerb.DONE)
    match = _PATTERN.match(normalised)
    if match is None:
        return None
    object_type = type_from_natural(match["name"])
    if object_type is None:
        return None
    skill = Skill(SkillVerb(match["verb"]), object_type)
    return skill if skill in _vocabulary() else None


@lru_cache(maxsize=512)
def canonical_text(skill: Skill) -> str:
    """`Skill.text`, cached: the executor records it for every step."""
    return skill.text
