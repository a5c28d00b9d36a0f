"""The skill vocabulary and ALFRED object categories."""

from talkdem.skills.categories import (
    ObjectCategories,
    categories,
    indefinite_article,
    natural_name,
    type_from_natural,
)
from talkdem.skills.vocabulary import Skill, SkillVerb, skill_texts, vocabulary

__all__ = [
    "ObjectCategories",
    "Skill",
    "SkillVerb",
    "categories",
    "indefinite_article",
    "natural_name",
    "skill_texts",
    "type_from_natural",
    "vocabulary",
]
