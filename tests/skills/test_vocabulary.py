"""The 214-skill vocabulary built from ALFRED's object categories."""

from __future__ import annotations

from collections import Counter

from talkdem.skills import SkillVerb, categories, natural_name, skill_texts, type_from_natural, vocabulary


def test_vocabulary_has_214_distinct_skills() -> None:
    skills = vocabulary()
    assert len(skills) == 214
    assert len(skill_texts()) == 214


def test_skill_counts_per_verb_follow_the_categories() -> None:
    per_verb = Counter(skill.verb for skill in vocabulary())
    cats = categories()
    assert per_verb[SkillVerb.FIND] == len(cats.findable) == 80
    assert per_verb[SkillVerb.PICK_UP] == per_verb[SkillVerb.PUT_DOWN] == len(cats.pickupable) == 53
    assert per_verb[SkillVerb.OPEN] == per_verb[SkillVerb.CLOSE] == 7
    assert per_verb[SkillVerb.SLICE] == 5
    assert per_verb[SkillVerb.TURN_ON] == per_verb[SkillVerb.TURN_OFF] == 4
    assert per_verb[SkillVerb.DONE] == 1


def test_natural_names_and_articles() -> None:
    texts = skill_texts()
    assert "find an apple" in texts and "find a desk lamp" in texts and "find a CD" in texts
    assert "pick up the remote control" in texts and "turn on the floor lamp" in texts
    assert "slice the bread" in texts and "open the fridge" in texts and "done" in texts
    assert natural_name("DeskLamp") == "desk lamp" and natural_name("CD") == "CD"
    assert type_from_natural("Desk  Lamp") == "DeskLamp" and type_from_natural("spaceship") is None


def test_every_category_member_is_findable() -> None:
    cats = categories()
    findable = set(cats.findable)
    for group in (cats.pickupable, cats.openable, cats.sliceable, cats.toggleable):
        assert set(group) <= findable
