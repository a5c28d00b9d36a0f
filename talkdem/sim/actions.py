"""One executor per skill verb: a precondition that picks the object or says why not, and an effect.

Messages are LoTa-Bench's (`thor_connector.py`) and AI2-THOR's; a failed precondition leaves the state
unchanged except where AI2-THOR changes it anyway (a failed put drops the held object to the floor).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from enum import StrEnum

from talkdem.sim.affordances import OBJECT_SPECIFIC_RECEPTACLES
from talkdem.sim.goals import REACH_M
from talkdem.sim.state import SimState, whole_object_id
from talkdem.skills import Skill, SkillVerb, natural_name

__all__ = [
    "ACTIONS",
    "ActionRule",
    "FailureKind",
    "StepFailure",
    "Target",
    "at_hand",
    "drop_held",
    "find_order",
    "put_order",
    "remember_destination",
]


class FailureKind(StrEnum):
    """Why a step failed; an error classifier reads this instead of parsing messages."""

    NOT_SUPPORTED = "not_supported"
    """The string is not one of the 214 skills."""
    NOT_FOUND = "not_found"
    """No instance of the named type in the scene, or none at hand."""
    NOT_VISIBLE = "not_visible"
    """The object is inside a closed receptacle."""
    HANDS_FULL = "hands_full"
    HANDS_EMPTY = "hands_empty"
    PUT_FAILED = "put_failed"
    """No receptacle at the current location, a closed one, or one inside the held object."""
    OPEN_FAILED = "open_failed"
    CLOSE_FAILED = "close_failed"
    TURN_ON_FAILED = "turn_on_failed"
    TURN_OFF_FAILED = "turn_off_failed"
    SLICE_FAILED = "slice_failed"


@dataclass(frozen=True)
class StepFailure:
    """A failed precondition: the kind, the simulator's message, and the object involved (if any)."""

    kind: FailureKind
    message: str
    object_id: str | None = None
    drops_held: bool = False
    """LoTa-Bench drops the held object to the floor after this failure (a `put down` that failed)."""


@dataclass(frozen=True)
class Target:
    """What a step acts on: the object, and for `put down` the receptacle."""

    object_id: str | None
    receptacle_id: str | None = None


Precondition = Callable[[SimState, Skill], "Target | StepFailure"]
Effect = Callable[[SimState, Target], None]


@dataclass(frozen=True)
class ActionRule:
    """Precondition and effect of one verb."""

    precondition: Precondition
    effect: Effect


def _name(skill: Skill) -> str:
    return natural_name(skill.object_type)


def _at_location(state: SimState, object_id: str) -> bool:
    """The object is the current location, a slice of it, inside it, or holds it."""
    loc = state.location
    if loc is None:
        return False
    return (
        object_id == loc
        or whole_object_id(object_id) == loc
        or state.contains(loc, object_id)
        or state.contains(object_id, loc)
    )


def at_hand(state: SimState, skill_type: str) -> list[str]:
    """Instances an interaction can reach: at the current location first, then within `REACH_M` by distance.

    Visible ones come before ones inside a closed receptacle, and slices before whole objects.
    """
    ranked = []
    for oid in state.instances(skill_type):
        if _at_location(state, oid):
            rank = 0
        elif state.distance(oid) <= REACH_M:
            rank = 1
        else:
            continue
        hidden = state.inside_closed(oid) is not None
        ranked.append((hidden, rank, "Sliced" not in oid, state.distance(oid), oid))
    return [entry[-1] for entry in sorted(ranked)]


def visible(state: SimState, object_id: str) -> bool:
    """AI2-THOR's `visible` (in view and within `visibilityDistance`), symbolically: carried, or not inside a
    closed receptacle and at the current location or within `REACH_M`. Which way the agent faces is not modelled."""
    if state.is_carried(object_id):
        return True
    if state.inside_closed(object_id) is not None:
        return False
    return _at_location(state, object_id) or state.distance(object_id) <= REACH_M


def find_order(state: SimState, skill_type: str) -> list[str]:
    """Instances in the order LoTa-Bench's `nav_obj` ranks them (`get_obj_id_from_name` with the visibility
    priority): outside closed receptacles, then not a loaded stove burner, then visible, then slices, then nearest."""
    ranked = []
    for oid in state.instances(skill_type):
        spec = state.specs[oid]
        busy_burner = spec.object_type == "StoveBurner" and bool(state.contents.get(oid))
        hidden = state.inside_closed(oid) is not None
        seen = visible(state, oid)
        # Calibration (docs/simulator.md): among visible fixtures of a type, one holding something first.
        empty_fixture = seen and spec.receptacle and not spec.pickupable and not state.contents.get(oid)
        ranked.append(
            (
                hidden,
                busy_burner,
                not seen,
                empty_fixture,
                "Sliced" not in oid,
                0.0 if state.is_carried(oid) else state.distance(oid),
                oid,
            )
        )
    return [entry[-1] for entry in sorted(ranked)]


# --- find -------------------------------------------------------------------------------------------


def remember_destination(state: SimState, skill: Skill | None) -> None:
    """LoTa-Bench `llm_skill_interact`: every skill but `put down` and `open` forgets the destination (an
    unparsable one too); `find` records the type it names before it moves, so a failed find records it as well."""
    if skill is None or skill.verb not in (SkillVerb.PUT_DOWN, SkillVerb.OPEN):
        state.destination = None
    if skill is not None and skill.verb is SkillVerb.FIND:
        state.destination = skill.object_type


def _find_pre(state: SimState, skill: Skill) -> Target | StepFailure:
    order = find_order(state, skill.object_type)
    if not order:
        return StepFailure(FailureKind.NOT_FOUND, f"Cannot find {_name(skill)}")
    return Target(order[0])


def _find_effect(state: SimState, target: Target) -> None:
    assert target.object_id is not None
    state.location = target.object_id
    state.agent = state.position(target.object_id)


# --- pick up / put down -----------------------------------------------------------------------------


def _pick_pre(state: SimState, skill: Skill) -> Target | StepFailure:
    if state.held is not None:
        held = natural_name(state.specs[state.held].skill_type)
        return StepFailure(FailureKind.HANDS_FULL, f"Robot is currently holding {held}", state.held)
    candidates = [o for o in at_hand(state, skill.object_type) if state.specs[o].pickupable]
    if not candidates:
        return StepFailure(FailureKind.NOT_FOUND, f"Cannot find {_name(skill)} to pick up")
    chosen = candidates[0]
    hidden_by = state.inside_closed(chosen)
    if hidden_by is not None:
        where = state.specs[hidden_by].object_type
        return StepFailure(FailureKind.NOT_VISIBLE, f"{_name(skill)} is not visible because it is in {where}", chosen)
    return Target(chosen)


def _pick_effect(state: SimState, target: Target) -> None:
    assert target.object_id is not None
    state.detach(target.object_id)
    state.held = target.object_id
    state.mark_moved(target.object_id)


def put_order(state: SimState, skill_type: str) -> list[str]:
    """Receptacles of the destination type in the order LoTa-Bench's `put` tries them (`get_obj_id_from_name`
    without the visibility priority): not inside a closed receptacle, not a loaded stove burner, nearest."""
    ranked = []
    for oid in state.instances(skill_type):
        busy_burner = state.specs[oid].object_type == "StoveBurner" and bool(state.contents.get(oid))
        ranked.append((state.inside_closed(oid) is not None, busy_burner, state.distance(oid), oid))
    return [entry[-1] for entry in sorted(ranked)]


def _accepts(state: SimState, held: str, receptacle: str) -> bool:
    """AI2-THOR `PlaceHeldObject` with `forceAction=True`: a visible receptacle, open if it opens, and an
    object-specific receptacle only for its types and only while empty. Type restrictions are skipped."""
    spec = state.specs[receptacle]
    if not spec.receptacle or receptacle == held or state.is_carried(receptacle):
        return False
    if state.inside_closed(receptacle) is not None:
        return False
    if receptacle != state.location and state.distance(receptacle) > REACH_M:
        return False
    if spec.must_be_open and not state.is_open.get(receptacle, False):
        return False
    allowed = OBJECT_SPECIFIC_RECEPTACLES.get(spec.object_type)
    return allowed is None or (state.specs[held].object_type in allowed and not state.contents.get(receptacle))


# LoTa-Bench drops the object when `put`'s message is longer than this; "Cannot find Mug" keeps it in hand.
_DROP_MESSAGE_LENGTH = 16


def _put_pre(state: SimState, skill: Skill) -> Target | StepFailure:
    held = state.held
    if held is None:
        return StepFailure(FailureKind.HANDS_EMPTY, "Robot is not holding any object")
    destination = state.destination
    if destination is None:  # LoTa-Bench: no destination -> drop()
        return StepFailure(FailureKind.PUT_FAILED, "put down failed", held, drops_held=True)
    tried: list[str] = []
    for receptacle in put_order(state, destination)[:2]:  # LoTa tries the closest, then the next closest
        tried.append(receptacle)
        if _accepts(state, held, receptacle):
            return Target(held, receptacle)
    # LoTa's last attempt looks for a sub-object (basin, slice) of the type other than the one it tried last;
    # its message decides whether the object is dropped.
    inherited = [o for o in state.instances(destination) if o.count("|") == 4 and o not in tried[-1:]]
    message = f"Putting the object on {destination} failed" if inherited else f"Cannot find {destination}"
    if len(message) > _DROP_MESSAGE_LENGTH:
        return StepFailure(FailureKind.PUT_FAILED, "put down failed", held, drops_held=True)
    return StepFailure(FailureKind.PUT_FAILED, message, held)


def _put_effect(state: SimState, target: Target) -> None:
    assert target.object_id is not None and target.receptacle_id is not None
    state.held = None
    state.attach(target.object_id, target.receptacle_id)
    state.mark_moved(target.object_id)


def drop_held(state: SimState) -> None:
    """A dropped object lies on the floor where the agent stands, in no receptacle (AI2-THOR `DropHandObject`)."""
    if state.held is None:
        return
    dropped, state.held = state.held, None
    state.mark_moved(dropped)
    state.moved[dropped] = state.agent


# --- open / close -----------------------------------------------------------------------------------


def _reachable(state: SimState, skill: Skill, flag: str, verb: str) -> str | StepFailure:
    candidates = [o for o in at_hand(state, skill.object_type) if getattr(state.specs[o], flag)]
    visible = [o for o in candidates if state.inside_closed(o) is None]
    if not visible:
        return StepFailure(FailureKind.NOT_FOUND, f"Cannot find {_name(skill)} to {verb}")
    return visible[0]


def _open_pre(state: SimState, skill: Skill) -> Target | StepFailure:
    found = _reachable(state, skill, "openable", "open")
    if isinstance(found, StepFailure):
        return found
    # AI2-THOR refuses to open a running microwave.
    if state.is_open.get(found, False) or state.is_toggled.get(found, False):
        return StepFailure(FailureKind.OPEN_FAILED, "Open action failed", found)
    return Target(found)


def _open_effect(state: SimState, target: Target) -> None:
    assert target.object_id is not None
    state.is_open[target.object_id] = True


def _close_pre(state: SimState, skill: Skill) -> Target | StepFailure:
    found = _reachable(state, skill, "openable", "close")
    if isinstance(found, StepFailure):
        return found
    if not state.is_open.get(found, False):
        return StepFailure(FailureKind.CLOSE_FAILED, "Close action failed", found)
    return Target(found)


def _close_effect(state: SimState, target: Target) -> None:
    assert target.object_id is not None
    state.is_open[target.object_id] = False
    # ALFRED (env/thor_env.py update_states): closing the fridge door cools everything inside.
    if state.specs[target.object_id].object_type == "Fridge":
        state.cooled.update(state.receptacle_object_ids(target.object_id))


# --- turn on / turn off -----------------------------------------------------------------------------


def _turn_on_pre(state: SimState, skill: Skill) -> Target | StepFailure:
    found = _reachable(state, skill, "toggleable", "turn on")
    if isinstance(found, StepFailure):
        return found
    # AI2-THOR: a microwave runs only with its door closed.
    if state.is_toggled.get(found, False) or state.is_open.get(found, False):
        return StepFailure(FailureKind.TURN_ON_FAILED, "Turn on action failed", found)
    return Target(found)


def _turn_on_effect(state: SimState, target: Target) -> None:
    device = target.object_id
    assert device is not None
    state.is_toggled[device] = True
    kind = state.specs[device].object_type
    # ALFRED update_states: the microwave heats its contents, the faucet cleans its basin's contents.
    if kind == "Microwave":
        state.heated.update(state.receptacle_object_ids(device))
    elif kind == "Faucet":
        basins = sorted(
            (o for o in state.instances("Sink") if state.specs[o].object_type == "SinkBasin"),
            key=lambda b: (_spec_distance(state, b, device), b),
        )
        if basins:
            washed = state.receptacle_object_ids(basins[0])
            state.cleaned.update(washed)
            state.dirty.difference_update(washed)


def _spec_distance(state: SimState, a: str, b: str) -> float:
    (ax, az), (bx, bz) = state.specs[a].xz, state.specs[b].xz
    return float((ax - bx) ** 2 + (az - bz) ** 2)


def _turn_off_pre(state: SimState, skill: Skill) -> Target | StepFailure:
    found = _reachable(state, skill, "toggleable", "turn off")
    if isinstance(found, StepFailure):
        return found
    if not state.is_toggled.get(found, False):
        return StepFailure(FailureKind.TURN_OFF_FAILED, "Turn off action failed", found)
    return Target(found)


def _turn_off_effect(state: SimState, target: Target) -> None:
    assert target.object_id is not None
    state.is_toggled[target.object_id] = False


# --- slice ------------------------------------------------------------------------------------------


def _slice_pre(state: SimState, skill: Skill) -> Target | StepFailure:
    # LoTa-Bench `slice` sends SliceObject with no check of the hand; AI2-THOR needs a visible, unsliced
    # sliceable that is not the object in the agent's hand.
    reachable = [o for o in at_hand(state, skill.object_type) if not state.is_carried(o)]
    if not reachable:
        return StepFailure(FailureKind.NOT_FOUND, f"Cannot find {_name(skill)} to slice")
    candidates = [o for o in reachable if state.specs[o].sliceable and o not in state.sliced]
    if not candidates or state.inside_closed(candidates[0]) is not None:
        return StepFailure(FailureKind.SLICE_FAILED, "Slice action failed", (candidates or reachable)[0])
    return Target(candidates[0])


def _slice_effect(state: SimState, target: Target) -> None:
    whole = target.object_id
    assert whole is not None
    receptacle, moved = state.parent.get(whole), state.moved.get(whole, "unmoved")
    state.detach(whole)
    state.present.discard(whole)
    state.sliced.add(whole)
    for piece in state.specs[whole].slices:
        state.present.add(piece)
        if receptacle is not None:
            state.attach(piece, receptacle)
        if moved != "unmoved":
            state.moved[piece] = state.moved[whole]


# --- done -------------------------------------------------------------------------------------------


def _done_pre(state: SimState, skill: Skill) -> Target | StepFailure:
    return Target(None)


def _no_effect(state: SimState, target: Target) -> None:
    return None


ACTIONS: dict[SkillVerb, ActionRule] = {
    SkillVerb.DONE: ActionRule(_done_pre, _no_effect),
    SkillVerb.FIND: ActionRule(_find_pre, _find_effect),
    SkillVerb.PICK_UP: ActionRule(_pick_pre, _pick_effect),
    SkillVerb.PUT_DOWN: ActionRule(_put_pre, _put_effect),
    SkillVerb.OPEN: ActionRule(_open_pre, _open_effect),
    SkillVerb.CLOSE: ActionRule(_close_pre, _close_effect),
    SkillVerb.TURN_ON: ActionRule(_turn_on_pre, _turn_on_effect),
    SkillVerb.TURN_OFF: ActionRule(_turn_off_pre, _turn_off_effect),
    SkillVerb.SLICE: ActionRule(_slice_pre, _slice_effect),
}
"""The dispatch table: every verb of the vocabulary has exactly one rule."""
