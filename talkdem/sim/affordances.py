"""Type-level object affordances as data (AI2-THOR object metadata flags, ALFRED categories).

Every rule in the executor asks these tables, never `if object_type == ...` in an action body.
"""

from __future__ import annotations

from functools import cache

from talkdem.skills import categories

__all__ = [
    "BASIN_OF",
    "DIRTYABLE_TYPES",
    "KNIFE_TYPES",
    "MUST_BE_OPEN_TYPES",
    "OBJECT_SPECIFIC_RECEPTACLES",
    "SLICE_COUNT",
    "STARTS_OPEN_TYPES",
    "TypeFlags",
    "skill_type_of",
    "type_flags",
    "vocabulary_type",
]

# The vocabulary names a basin by its parent fixture: `find a sink` walks to `Sink|..|SinkBasin`.
BASIN_OF = {"Sink": "SinkBasin", "Bathtub": "BathtubBasin"}
_PARENT_OF_BASIN = {basin: parent for parent, basin in BASIN_OF.items()}

# AI2-THOR `ObjectMetadata.receptacle` types that the 31 vocabulary receptacles leave out but scenes use
# (an object can start in them; the planner just cannot name them).
_EXTRA_RECEPTACLES = frozenset(
    {"SinkBasin", "BathtubBasin", "TVStand", "HandTowelHolder", "TowelHolder", "LaundryHamper", "Stool"}
)

# AI2-THOR `MustBeOpenToPlaceObjectsIn` (simulator.md): putting into these needs an open door.
MUST_BE_OPEN_TYPES = frozenset({"Drawer", "Cabinet", "LaundryHamper", "Microwave", "Fridge", "Box"})

# Openable types that start open in AI2-THOR scenes (ALFRED trajectories close laptops and fill boxes
# without an OpenObject first).
STARTS_OPEN_TYPES = frozenset({"Box", "Laptop"})

# Knife types (hazard rule iii). Slicing itself does not need one: ALFRED's knife check sits in
# `env/thor_env.py` `to_thor_api_exec`, which LoTa-Bench's skill layer does not call (docs/simulator.md).
KNIFE_TYPES = frozenset({"Knife", "ButterKnife"})

# AI2-THOR `ObjectSpecificReceptacle`s: `PlaceHeldObject` checks the held type and that the attach point is free
# before it looks at `forceAction`, so these hold only these types, one object at a time. The types are those of
# ALFRED `gen/constants.py` `VAL_RECEPTACLE_OBJECTS` for the same receptacles.
OBJECT_SPECIFIC_RECEPTACLES: dict[str, frozenset[str]] = {
    "CoffeeMachine": frozenset({"Mug"}),
    "StoveBurner": frozenset({"Kettle", "Pan", "Pot"}),
    "Toaster": frozenset({"BreadSliced"}),
    "ToiletPaperHanger": frozenset({"ToiletPaper"}),
    "TowelHolder": frozenset({"Towel"}),
    "HandTowelHolder": frozenset({"HandTowel"}),
}

# Number of `<Type>Sliced_<i>` pieces AI2-THOR spawns. Only their existence matters to goals and hazards,
# so the counts are kept small and fixed; ids follow AI2-THOR (`Apple|x|y|z|AppleSliced_0`).
SLICE_COUNT = {"Apple": 3, "Bread": 3, "Lettuce": 3, "Potato": 3, "Tomato": 3}

# Objects that ALFRED's `dirty_and_empty` scene flag starts dirty (AI2-THOR `dirtyable`).
DIRTYABLE_TYPES = frozenset({"Bowl", "Cup", "Mug", "Pan", "Plate", "Pot", "Cloth"})


class TypeFlags:
    """Fixed affordances of one AI2-THOR object type."""

    __slots__ = ("openable", "pickupable", "receptacle", "sliceable", "toggleable")

    def __init__(self, *, pickupable: bool, receptacle: bool, openable: bool, toggleable: bool, sliceable: bool):
        self.pickupable = pickupable
        self.receptacle = receptacle
        self.openable = openable
        self.toggleable = toggleable
        self.sliceable = sliceable


@cache
def _type_case_map() -> dict[str, str]:
    cats = categories()
    every = set(cats.findable) | set(cats.receptacle) | set(cats.pickupable) | _EXTRA_RECEPTACLES
    return {name.lower(): name for name in every}


def vocabulary_type(object_type: str) -> str:
    """AI2-THOR spellings differ in case between files (`Glassbottle`); map to the vocabulary's spelling."""
    return _type_case_map().get(object_type.lower(), object_type)


def skill_type_of(object_type: str) -> str:
    """The type a skill names: `SinkBasin` -> `Sink`, `AppleSliced` -> `Apple`."""
    if object_type in _PARENT_OF_BASIN:
        return _PARENT_OF_BASIN[object_type]
    return object_type.removesuffix("Sliced")


@cache
def type_flags(object_type: str) -> TypeFlags:
    """Affordances of an AI2-THOR type; slices are pickupable and nothing else."""
    cats = categories()
    if object_type.endswith("Sliced"):
        return TypeFlags(pickupable=True, receptacle=False, openable=False, toggleable=False, sliceable=False)
    return TypeFlags(
        pickupable=object_type in cats.pickupable,
        receptacle=object_type in cats.receptacle or object_type in _EXTRA_RECEPTACLES,
        openable=object_type in cats.openable,
        toggleable=object_type in cats.toggleable,
        sliceable=object_type in cats.sliceable,
    )
