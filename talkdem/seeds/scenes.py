"""Scene data of the AI2-THOR floor plans: object types present and openable receptacles."""

from __future__ import annotations

import json
from functools import cache
from pathlib import Path
from typing import Any

from talkdem.paths import floorplans_dir
from talkdem.seeds.errors import SeedFormatError
from talkdem.seeds.records import AgentPose, OpenableReceptacle

__all__ = ["load_openable_receptacles", "load_scene_objects"]


def _read_json(path: Path) -> Any:
    if not path.is_file():
        raise SeedFormatError(path, "", "file not found (is the floor-plan folder right?)")
    try:
        return json.loads(path.read_text())
    except json.JSONDecodeError as exc:
        raise SeedFormatError(path, "", f"not valid JSON (line {exc.lineno}: {exc.msg})") from exc


@cache
def load_scene_objects(floor_plan: str, folder: Path | None = None) -> tuple[str, ...]:
    """Sorted object types of `FloorPlan<N>` from `FloorPlan<N>-objects.json`."""
    path = (folder or floorplans_dir()) / f"{floor_plan}-objects.json"
    raw = _read_json(path)
    if not isinstance(raw, list) or not all(isinstance(t, str) for t in raw):
        raise SeedFormatError(path, "", "expected a JSON list of object-type strings")
    return tuple(sorted(set(raw)))


@cache
def load_openable_receptacles(floor_plan: str, folder: Path | None = None) -> tuple[OpenableReceptacle, ...]:
    """Openable receptacles of `FloorPlan<N>` (sorted by id) with the agent pose ALFRED opens them from."""
    path = (folder or floorplans_dir()) / f"{floor_plan}-openable.json"
    raw = _read_json(path)
    if not isinstance(raw, dict):
        raise SeedFormatError(path, "", "expected a JSON object mapping object ids to [x, z, rotation, horizon]")
    receptacles = []
    for object_id in sorted(raw):
        pose = raw[object_id]
        if not (isinstance(pose, list) and len(pose) == 4 and all(isinstance(v, int | float) for v in pose)):
            raise SeedFormatError(path, object_id, "expected [x, z, rotation, horizon] numbers")
        receptacles.append(
            OpenableReceptacle(
                object_id=object_id,
                object_type=object_id.split("|", 1)[0],
                agent_pose=AgentPose(x=pose[0], z=pose[1], rotation=pose[2], horizon=pose[3]),
            )
        )
    return tuple(receptacles)
