"""Typed records for one ALFRED seed trajectory (the REI-Bench seed pool is ALFRED `json_2.1.0`)."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = [
    "AgentPose",
    "Interaction",
    "ObjectPose",
    "ObjectToggle",
    "OpenableReceptacle",
    "PddlParams",
    "PickupSource",
    "SeedScene",
    "SeedTask",
    "Vector3",
]


@dataclass(frozen=True)
class PddlParams:
    """The ALFRED task parameters (`pddl_params`)."""

    object_target: str
    """Type of the object to manipulate, e.g. `Apple`."""
    parent_target: str
    """Type of the destination receptacle (empty for look-at tasks)."""
    mrecep_target: str
    """Type of the movable receptacle of stack-and-place tasks (else empty)."""
    toggle_target: str
    """Type of the lamp of look-at tasks (else empty)."""
    object_sliced: bool
    """True when the target must be sliced (the goal then concerns `<Target>Sliced`)."""


@dataclass(frozen=True)
class Vector3:
    """A position in AI2-THOR world coordinates (metres)."""

    x: float
    y: float
    z: float


@dataclass(frozen=True)
class ObjectPose:
    """One entry of `scene.object_poses`: where ALFRED placed a pickupable object."""

    object_name: str
    """AI2-THOR object name, `<Type>_<hash>` (several poses can share a name: copies of one asset)."""
    object_type: str
    position: Vector3


@dataclass(frozen=True)
class ObjectToggle:
    """One entry of `scene.object_toggles`: the initial on/off state of a toggleable type."""

    object_type: str
    is_on: bool


@dataclass(frozen=True)
class AgentPose:
    """The agent's pose: position on the floor plane, yaw and camera horizon (degrees)."""

    x: float
    z: float
    rotation: float
    horizon: float


@dataclass(frozen=True)
class OpenableReceptacle:
    """An openable receptacle of the scene (`FloorPlan<N>-openable.json`) and where ALFRED stands to open it."""

    object_id: str
    object_type: str
    agent_pose: AgentPose


@dataclass(frozen=True)
class SeedScene:
    """The initial scene of the trajectory (`scene`)."""

    floor_plan: str
    scene_num: int
    agent: AgentPose
    object_poses: tuple[ObjectPose, ...]
    object_toggles: tuple[ObjectToggle, ...]
    dirty_and_empty: bool
    """ALFRED's flag: receptacles start emptied and dirtyable objects start dirty."""
    random_seed: int
    scene_objects: tuple[str, ...]
    """Object types present in the floor plan (sorted)."""
    openable_receptacles: tuple[OpenableReceptacle, ...]


@dataclass(frozen=True)
class PickupSource:
    """Where the expert picked an object up (`high_pddl` `PickupObject.coordinateReceptacleObjectId`)."""

    object_id: str
    receptacle_type: str
    """Empty when ALFRED records no source receptacle (e.g. the object lay on the floor)."""
    receptacle_bounds: tuple[float, ...]
    """ALFRED's coordinate box of the receptacle (grid units, as stored)."""


@dataclass(frozen=True)
class Interaction:
    """One expert interaction low action (navigation and camera moves are dropped)."""

    action: str
    """AI2-THOR action: PickupObject, PutObject, OpenObject, CloseObject, ToggleObjectOn/Off, SliceObject."""
    object_id: str
    receptacle_id: str = ""
    """For PutObject: the receptacle the held object was put in."""


@dataclass(frozen=True)
class SeedTask:
    """One REI-Bench seed: an ALFRED trial with one of its language annotations."""

    task_id: str
    """The ALFRED trial id, e.g. `trial_T20190908_103828_466550`."""
    task_type: str
    task_name: str
    """The ALFRED task folder, e.g. `pick_heat_then_place_in_recep-AppleSliced-None-Fridge-11`."""
    repeat_idx: int
    """Which annotation of the trial this seed uses."""
    source_file: str
    """Path of the trajectory file relative to the `json_2.1.0` folder."""
    pddl_params: PddlParams
    scene: SeedScene
    instruction: str
    """The seed instruction: `turk_annotations.anns[repeat_idx].task_desc`."""
    high_descs: tuple[str, ...]
    pickup_sources: tuple[PickupSource, ...]
    interactions: tuple[Interaction, ...]

    @property
    def floor_plan(self) -> str:
        return self.scene.floor_plan
