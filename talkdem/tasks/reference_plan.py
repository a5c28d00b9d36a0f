"""Convert an ALFRED expert trajectory into a reference plan in the 214-skill vocabulary.

Rules (the simulator must accept every plan produced here):
- Each interaction low action becomes one skill: PickupObject -> `pick up the X`, PutObject -> `put down
  the X` (X = the held object; the destination is wherever the agent is), OpenObject/CloseObject ->
  `open`/`close`, ToggleObjectOn/Off -> `turn on`/`turn off`, SliceObject -> `slice`.
- A `find` precedes an interaction whose object changes, i.e. the object is neither the agent's current
  location (the last object found) nor inside it. The "inside" test is what keeps the fridge and microwave
  episodes right: after `open the fridge` the apple put inside earlier is picked up without a `find`
  (a `find an apple` there could walk to another apple that was never cooled).
- Every interaction is kept, including a `close X` right before `open X`: closing the fridge is what cools
  its contents (ALFRED marks objects cooled when the fridge door closes on them).
- The plan ends with `done`.
"""

from __future__ import annotations

from talkdem.seeds.records import SeedTask
from talkdem.skills import Skill, SkillVerb, skill_texts

__all__ = ["ReferencePlanError", "object_type_of", "reference_plan", "reference_skills"]

_VERB_OF_ACTION = {
    "PickupObject": SkillVerb.PICK_UP,
    "PutObject": SkillVerb.PUT_DOWN,
    "OpenObject": SkillVerb.OPEN,
    "CloseObject": SkillVerb.CLOSE,
    "ToggleObjectOn": SkillVerb.TURN_ON,
    "ToggleObjectOff": SkillVerb.TURN_OFF,
    "SliceObject": SkillVerb.SLICE,
}

# AI2-THOR sub-objects that the skill vocabulary names by their parent: `Sink|..|SinkBasin` is "the sink".
_BASINS = frozenset({"SinkBasin", "BathtubBasin"})


class ReferencePlanError(ValueError):
    """A trajectory cannot be expressed in the skill vocabulary; the message names the task and step."""


def object_type_of(object_id: str) -> str:
    """The vocabulary type of an AI2-THOR id: `Sink|..|SinkBasin` -> `Sink`, `Apple|..|AppleSliced_1` -> `Apple`."""
    parts = object_id.split("|")
    if len(parts) > 4 and parts[4] in _BASINS:
        return parts[0]
    if len(parts) == 1 and parts[0] in _BASINS:
        return parts[0].removesuffix("Basin")
    return parts[0]


def _whole_object_id(object_id: str) -> str:
    """A slice or basin shares identity with its parent object for location purposes."""
    return "|".join(object_id.split("|")[:4])


def reference_skills(seed: SeedTask) -> list[Skill]:
    """The reference plan as `Skill` records (see the module docstring for the rules)."""
    # Where each object is, as far as the trajectory tells: its source receptacle, then wherever it was put.
    inside: dict[str, str] = {
        _whole_object_id(src.object_id): src.receptacle_type for src in seed.pickup_sources if src.receptacle_type
    }
    location = ""  # whole id of the object last found
    skills: list[Skill] = []
    for step, action in enumerate(seed.interactions):
        verb = _VERB_OF_ACTION[action.action]
        acted_on = action.receptacle_id if verb is SkillVerb.PUT_DOWN else action.object_id
        place = _whole_object_id(acted_on)
        location_type = object_type_of(location) if location else ""
        inside_location = bool(location) and inside.get(place) in {location, location_type}
        if place != location and not inside_location:
            skills.append(Skill(SkillVerb.FIND, object_type_of(acted_on)))
            location = place
        skill = Skill(verb, object_type_of(action.object_id))
        if skill.text not in skill_texts():
            raise ReferencePlanError(
                f"task {seed.task_id} ({seed.source_file}): interaction {step} {action.action} "
                f"{action.object_id} maps to '{skill.text}', which is not in the skill vocabulary"
            )
        skills.append(skill)
        if verb is SkillVerb.PUT_DOWN:
            inside[_whole_object_id(action.object_id)] = place
        elif verb is SkillVerb.PICK_UP:
            inside.pop(place, None)
    skills.append(Skill(SkillVerb.DONE))
    for skill in skills:
        if skill.text not in skill_texts():
            raise ReferencePlanError(f"task {seed.task_id}: '{skill.text}' is not in the skill vocabulary")
    return skills


def reference_plan(seed: SeedTask) -> list[str]:
    """The reference plan as skill strings, ending with `done`."""
    return [skill.text for skill in reference_skills(seed)]
