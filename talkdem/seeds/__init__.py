"""Reading the REI-Bench seed pool: ALFRED trajectories and AI2-THOR scene lists."""

from talkdem.seeds.errors import SeedFormatError
from talkdem.seeds.reader import INTERACTION_ACTIONS, iter_seed_files, load_seed_pool, read_seed_file
from talkdem.seeds.records import (
    AgentPose,
    Interaction,
    ObjectPose,
    ObjectToggle,
    OpenableReceptacle,
    PddlParams,
    PickupSource,
    SeedScene,
    SeedTask,
    Vector3,
)
from talkdem.seeds.scenes import load_openable_receptacles, load_scene_objects

__all__ = [
    "INTERACTION_ACTIONS",
    "AgentPose",
    "Interaction",
    "ObjectPose",
    "ObjectToggle",
    "OpenableReceptacle",
    "PddlParams",
    "PickupSource",
    "SeedFormatError",
    "SeedScene",
    "SeedTask",
    "Vector3",
    "iter_seed_files",
    "load_openable_receptacles",
    "load_scene_objects",
    "load_seed_pool",
    "read_seed_file",
]
