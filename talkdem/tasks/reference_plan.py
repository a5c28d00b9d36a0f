"""Convert an ALFRED expert trajectory into a reference plan in the 214-skill vocabulary.

Rules (the simulator must accept every plan produced here):
- Each interaction low action becomes one skill: PickupObject -> `pick up the X`, PutObject -> `put down
  the X` (X = the held object; the destination is wherever the agent is), OpenObject/CloseObject ->
  `open`/`close`, ToggleObjectOn/Off -> `turn on`/`turn off`, SliceObject -> `slice`.
- A `find` precedes an interaction whose object changes, i.e. the object is neither the agent's current
  location (the last object found) nor inside it. The "inside" test is what keeps the fridge and microwave
  episodes right: after `open the fridge` the apple put inside earlier is picked up without a `find`
  (a `find an apple` there could walk to another apple that was never cooled). "Inside" is decided per
  receptacle instance: an object put somewhere is inside that instance; an object's source receptacle is
  matched by type and floor position (ALFRED's recorded box), so a watch on another shelf is still found.
- `put down` puts into the receptacle type the last `find` named, and LoTa-Bench forgets that destination
  after any skill other than `put down` and `open`; so a `put down` is preceded by a `find` of its
  destination unless the destination is the location *and* only `put down`/`open` steps came since that
  `find` (the expert who slices the apple in the open fridge and then puts the knife there walks back to
  the fridge: `find a fridge` again).
- Every interaction is kept, including a `close X` right before `open X`: closing the fridge is what cools
  its contents (ALFRED marks objects cooled when the fridge door closes on them).
- The plan ends with `done`.
"""

from __future__ import annotations

from dataclasses import dataclass

from talkdem.seeds.records import SeedTask
from talkdem.skills import Skill, SkillVerb, skill_texts

__all__ = ["ReferencePlanError", "object_type_of", "reference_plan", "reference_skills", "reference_steps"]

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

# A source receptacle and a location instance closer than this on the floor plane are the same object.
_SAME_PLACE_METRES = 0.15


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


@dataclass(frozen=True)
class _Place:
    """Where an object sits: a receptacle instance (after a put) or a type and floor position (its source)."""

    object_type: str
    x: float | None = None
    z: float | None = None
    instance: str = ""


def _coordinates(object_id: str) -> tuple[float, float] | None:
    parts = object_id.split("|")
    try:
        return float(parts[1]), float(parts[3])
    except (IndexError, ValueError):
        return None


def _source_place(receptacle_type: str, bounds: tuple[float, ...]) -> _Place:
    # ALFRED stores the source receptacle as a grid box [x, x, z, z, y, y] in quarter-metre units.
    kind = object_type_of(receptacle_type)
    if len(bounds) == 6:
        return _Place(kind, x=bounds[0] / 4, z=bounds[2] / 4)
    return _Place(kind)


def _is_at(place: _Place | None, location: str) -> bool:
    """Whether an object at `place` is reachable without moving from `location` (an instance id)."""
    if place is None or not location:
        return False
    if place.instance:
        return place.instance == location
    if place.object_type != object_type_of(location):
        return False
    here = _coordinates(location)
    if place.x is None or place.z is None or here is None:
        return False
    return abs(place.x - here[0]) < _SAME_PLACE_METRES and abs(place.z - here[1]) < _SAME_PLACE_METRES


def reference_skills(seed: SeedTask) -> list[Skill]:
    """The reference plan as `Skill` records (see the module docstring for the rules)."""
    return [skill for skill, _ in reference_steps(seed)]


def reference_steps(seed: SeedTask) -> list[tuple[Skill, str]]:
    """Each skill of the reference plan with, for a `find`, the whole id of the instance the expert went to
    (empty for other skills)."""
    # Where each object is, as far as the trajectory tells: its source receptacle, then wherever it was put.
    inside: dict[str, _Place] = {
        _whole_object_id(src.object_id): _source_place(src.receptacle_type, src.receptacle_bounds)
        for src in seed.pickup_sources
        if src.receptacle_type
    }
    location = ""  # whole id of the object last found
    destination = ""  # the location while LoTa-Bench still remembers it as the put-down destination
    skills: list[tuple[Skill, str]] = []
    for step, action in enumerate(seed.interactions):
        verb = _VERB_OF_ACTION[action.action]
        acted_on = action.receptacle_id if verb is SkillVerb.PUT_DOWN else action.object_id
        place = _whole_object_id(acted_on)
        # `put down` puts into wherever the agent is, so the destination itself must be the location;
        # other skills reach an object inside the location too (the apple in the open fridge).
        if verb is SkillVerb.PUT_DOWN:
            reachable = place == destination
        else:
            reachable = place == location or _is_at(inside.get(place), location)
        if not reachable:
            skills.append((Skill(SkillVerb.FIND, object_type_of(acted_on)), place))
            location = destination = place
        skill = Skill(verb, object_type_of(action.object_id))
        if skill.text not in skill_texts():
            raise ReferencePlanError(
                f"task {seed.task_id} ({seed.source_file}): interaction {step} {action.action} "
                f"{action.object_id} maps to '{skill.text}', which is not in the skill vocabulary"
            )
        skills.append((skill, ""))
        if verb not in (SkillVerb.PUT_DOWN, SkillVerb.OPEN):
            destination = ""
        if verb is SkillVerb.PUT_DOWN:
            inside[_whole_object_id(action.object_id)] = _Place(object_type_of(place), instance=place)
        elif verb is SkillVerb.PICK_UP:
            inside.pop(place, None)
    skills.append((Skill(SkillVerb.DONE), ""))
    return skills


def reference_plan(seed: SeedTask) -> list[str]:
    """The reference plan as skill strings, ending with `done`."""
    return [skill.text for skill in reference_skills(seed)]
