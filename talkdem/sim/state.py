"""The simulator state: fixed object specs shared by every episode, and the per-episode changing state.

Containment is stored once, as each object's direct receptacle (`parent`) mirrored by each receptacle's
direct contents (`contents`); AI2-THOR's transitive `parentReceptacles` / `receptacleObjectIds` are derived
from those two maps, so the two views cannot drift apart.
"""

from __future__ import annotations

import hashlib
import json
import math
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from typing import Any

__all__ = ["ObjectSpec", "SimState", "whole_object_id"]

XZ = tuple[float, float]


def whole_object_id(object_id: str) -> str:
    """A slice or basin id without its suffix: `Apple|1|2|3|AppleSliced_0` -> `Apple|1|2|3`."""
    return "|".join(object_id.split("|")[:4])


@dataclass(frozen=True, slots=True)
class ObjectSpec:
    """One object instance and its fixed affordances (AI2-THOR object metadata that never changes)."""

    object_id: str
    """AI2-THOR id, `Type|x|y|z` (basins and slices carry a fifth part)."""
    object_type: str
    """AI2-THOR type: `SinkBasin`, `AppleSliced`, `Apple`."""
    skill_type: str
    """The vocabulary type a skill names it by: `Sink`, `Apple`."""
    position: tuple[float, float, float]
    """Initial world position (metres)."""
    pickupable: bool
    receptacle: bool
    openable: bool
    toggleable: bool
    sliceable: bool
    must_be_open: bool
    """Objects can be put in it only while it is open (AI2-THOR `MustBeOpenToPlaceObjectsIn`)."""
    slices: tuple[str, ...] = ()
    """Ids of the slices that `slice` creates (empty unless sliceable)."""

    @property
    def xz(self) -> XZ:
        return (self.position[0], self.position[2])


@dataclass(slots=True)
class SimState:
    """Everything that changes during an episode; `copy()` is cheap (flat dicts and sets only)."""

    specs: Mapping[str, ObjectSpec]
    """Every instance that exists or can come to exist (slices), shared between episodes, never mutated."""
    by_skill_type: Mapping[str, tuple[str, ...]]
    """Instance ids per vocabulary type, sorted; shared."""
    present: set[str]
    """Ids that exist now (a sliced whole object leaves, its slices arrive)."""
    parent: dict[str, str]
    """Direct receptacle of each contained object (AI2-THOR `parentReceptacles[0]`)."""
    contents: dict[str, tuple[str, ...]]
    """Direct contents of each receptacle, mirroring `parent`."""
    is_open: dict[str, bool]
    is_toggled: dict[str, bool]
    dirty: set[str]
    sliced: set[str]
    moved: dict[str, XZ | None]
    """Objects no longer at their initial pose: None = follows its receptacle, else where it was dropped."""
    agent: XZ
    """Agent position on the floor plane."""
    location: str | None = None
    """The object the agent last went to with `find`."""
    destination: str | None = None
    """LoTa-Bench's `cur_receptacle`: the type the last `find` named (found or not), kept only while the skills
    after it are `put down` or `open`; where `put down` puts. Skill-layer memory, not world state: not hashed."""
    held: str | None = None
    heated: set[str] = field(default_factory=set)
    cooled: set[str] = field(default_factory=set)
    cleaned: set[str] = field(default_factory=set)

    def copy(self) -> SimState:
        return SimState(
            specs=self.specs,
            by_skill_type=self.by_skill_type,
            present=set(self.present),
            parent=dict(self.parent),
            contents=dict(self.contents),
            is_open=dict(self.is_open),
            is_toggled=dict(self.is_toggled),
            dirty=set(self.dirty),
            sliced=set(self.sliced),
            moved=dict(self.moved),
            agent=self.agent,
            location=self.location,
            destination=self.destination,
            held=self.held,
            heated=set(self.heated),
            cooled=set(self.cooled),
            cleaned=set(self.cleaned),
        )

    # --- containment (AI2-THOR's transitive views) ---------------------------------------------------

    def parent_receptacles(self, object_id: str) -> list[str]:
        """Receptacles containing the object, innermost first (transitive)."""
        chain: list[str] = []
        current = self.parent.get(object_id)
        while current is not None:
            chain.append(current)
            current = self.parent.get(current)
        return chain

    def receptacle_object_ids(self, receptacle_id: str) -> list[str]:
        """Everything inside the receptacle, at any depth, in a stable order."""
        found: list[str] = []
        stack = list(reversed(self.contents.get(receptacle_id, ())))
        while stack:
            item = stack.pop()
            found.append(item)
            stack.extend(reversed(self.contents.get(item, ())))
        return found

    def contains(self, receptacle_id: str, object_id: str) -> bool:
        return receptacle_id in self.parent_receptacles(object_id)

    def attach(self, object_id: str, receptacle_id: str) -> None:
        """Put the object directly in the receptacle, keeping both views mirrored."""
        self.detach(object_id)
        self.parent[object_id] = receptacle_id
        self.contents[receptacle_id] = (*self.contents.get(receptacle_id, ()), object_id)

    def detach(self, object_id: str) -> None:
        old = self.parent.pop(object_id, None)
        if old is not None:
            self.contents[old] = tuple(o for o in self.contents[old] if o != object_id)

    def inside_closed(self, object_id: str) -> str | None:
        """The outermost closed openable receptacle hiding the object, if any."""
        hidden_by = None
        for receptacle in self.parent_receptacles(object_id):
            if self.specs[receptacle].openable and not self.is_open.get(receptacle, False):
                hidden_by = receptacle
        return hidden_by

    def is_carried(self, object_id: str) -> bool:
        """Held, or inside the held object."""
        return self.held is not None and (object_id == self.held or self.contains(self.held, object_id))

    # --- positions --------------------------------------------------------------------------------

    def position(self, object_id: str) -> XZ:
        """Where the object is now: carried objects are at the agent, moved ones at their receptacle."""
        if self.is_carried(object_id):
            return self.agent
        current = object_id
        while current in self.moved:
            dropped = self.moved[current]
            if dropped is not None:
                return dropped
            receptacle = self.parent.get(current)
            if receptacle is None:
                return self.agent
            current = receptacle
        return self.specs[current].xz

    def distance(self, object_id: str) -> float:
        x, z = self.position(object_id)
        return math.hypot(x - self.agent[0], z - self.agent[1])

    def mark_moved(self, object_id: str) -> None:
        """The object and everything inside it now follow their receptacle."""
        self.moved[object_id] = None
        for inner in self.receptacle_object_ids(object_id):
            self.moved[inner] = None

    def instances(self, skill_type: str) -> Iterator[str]:
        """Present instances a skill naming this vocabulary type can refer to."""
        return (o for o in self.by_skill_type.get(skill_type, ()) if o in self.present)

    # --- serialization ----------------------------------------------------------------------------

    def to_json(self) -> dict[str, Any]:
        """The state in AI2-THOR metadata terms, keys sorted, so that it hashes stably."""
        objects = {}
        for object_id in sorted(self.present):
            spec = self.specs[object_id]
            record: dict[str, Any] = {
                "objectType": spec.object_type,
                "parentReceptacles": self.parent_receptacles(object_id),
            }
            if spec.receptacle:
                record["receptacleObjectIds"] = self.receptacle_object_ids(object_id)
            if spec.openable:
                record["isOpen"] = self.is_open.get(object_id, False)
            if spec.toggleable:
                record["isToggled"] = self.is_toggled.get(object_id, False)
            if spec.sliceable:
                record["isSliced"] = object_id in self.sliced
            if object_id in self.dirty:
                record["isDirty"] = True
            if object_id in self.moved:
                record["position"] = [round(v, 4) for v in self.position(object_id)]
            objects[object_id] = record
        return {
            "objects": objects,
            "agent": {"position": [round(v, 4) for v in self.agent], "location": self.location, "held": self.held},
            "heated": sorted(self.heated),
            "cooled": sorted(self.cooled),
            "cleaned": sorted(self.cleaned),
        }

    def state_hash(self) -> str:
        """sha256 of the canonical JSON of `to_json()`: equal states hash equal across runs and machines."""
        canonical = json.dumps(self.to_json(), sort_keys=True, separators=(",", ":"))
        return hashlib.sha256(canonical.encode()).hexdigest()
