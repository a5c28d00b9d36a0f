"""Reader for ALFRED preprocessed trajectory files (`json_2.1.0/<task>/<trial>/pp/ann_<r>.json`)."""

from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path
from typing import Any, TypeVar

from talkdem.paths import alfred_dir, floorplans_dir
from talkdem.seeds.errors import SeedFormatError
from talkdem.seeds.records import (
    AgentPose,
    Interaction,
    ObjectPose,
    ObjectToggle,
    PddlParams,
    PickupSource,
    SeedScene,
    SeedTask,
    Vector3,
)
from talkdem.seeds.scenes import load_openable_receptacles, load_scene_objects

__all__ = ["INTERACTION_ACTIONS", "iter_seed_files", "load_seed_pool", "read_seed_file"]

# Low actions that change the world; navigation and camera moves carry no information for a skill plan.
INTERACTION_ACTIONS = frozenset(
    {"PickupObject", "PutObject", "OpenObject", "CloseObject", "ToggleObjectOn", "ToggleObjectOff", "SliceObject"}
)

T = TypeVar("T")


class _Fields:
    """Typed access to a JSON object that names the file and the dotted field on any problem."""

    def __init__(self, path: Path, raw: Any, prefix: str = "") -> None:
        self.path, self.raw, self.prefix = path, raw, prefix
        if not isinstance(raw, dict):
            raise SeedFormatError(path, prefix or "<root>", f"expected a JSON object, got {type(raw).__name__}")

    def _name(self, key: str) -> str:
        return f"{self.prefix}.{key}" if self.prefix else key

    def get(self, key: str, kind: type[T] | tuple[type, ...]) -> T:
        if key not in self.raw:
            raise SeedFormatError(self.path, self._name(key), "missing")
        value = self.raw[key]
        # bool is an int in Python; a flag stored as 0/1 would be a format error, so check exactly.
        if not isinstance(value, kind) or (kind in (int, float) and isinstance(value, bool)):
            expected = kind.__name__ if isinstance(kind, type) else " or ".join(k.__name__ for k in kind)
            raise SeedFormatError(self.path, self._name(key), f"expected {expected}, got {type(value).__name__}")
        return value  # type: ignore[return-value]

    def sub(self, key: str) -> _Fields:
        return _Fields(self.path, self.get(key, dict), self._name(key))

    def items(self, key: str) -> list[_Fields]:
        return [_Fields(self.path, item, f"{self._name(key)}[{i}]") for i, item in enumerate(self.get(key, list))]

    def number(self, key: str) -> float:
        return float(self.get(key, (int, float)))


def _read_pddl(fields: _Fields) -> PddlParams:
    pddl = fields.sub("pddl_params")
    return PddlParams(
        object_target=pddl.get("object_target", str),
        parent_target=pddl.get("parent_target", str),
        mrecep_target=pddl.get("mrecep_target", str),
        toggle_target=pddl.get("toggle_target", str),
        object_sliced=pddl.get("object_sliced", bool),
    )


def _read_scene(fields: _Fields, floorplans: Path) -> SeedScene:
    scene = fields.sub("scene")
    init = scene.sub("init_action")
    poses = []
    for pose in scene.items("object_poses"):
        name = pose.get("objectName", str)
        position = pose.sub("position")
        poses.append(
            ObjectPose(
                object_name=name,
                object_type=name.split("_", 1)[0],
                position=Vector3(position.number("x"), position.number("y"), position.number("z")),
            )
        )
    toggles = tuple(
        ObjectToggle(object_type=t.get("objectType", str), is_on=t.get("isOn", bool))
        for t in scene.items("object_toggles")
    )
    floor_plan = scene.get("floor_plan", str)
    return SeedScene(
        floor_plan=floor_plan,
        scene_num=scene.get("scene_num", int),
        agent=AgentPose(
            x=init.number("x"), z=init.number("z"), rotation=init.number("rotation"), horizon=init.number("horizon")
        ),
        object_poses=tuple(poses),
        object_toggles=toggles,
        dirty_and_empty=scene.get("dirty_and_empty", bool),
        random_seed=scene.get("random_seed", int),
        scene_objects=load_scene_objects(floor_plan, floorplans),
        openable_receptacles=load_openable_receptacles(floor_plan, floorplans),
    )


def _read_pickup_sources(plan: _Fields) -> tuple[PickupSource, ...]:
    sources = []
    for step in plan.items("high_pddl"):
        action = step.sub("planner_action")
        if action.get("action", str) != "PickupObject":
            continue
        # Absent when the object lay on the floor or was spawned free-standing: no source receptacle.
        coordinate = action.raw.get("coordinateReceptacleObjectId") or ["", []]
        if len(coordinate) != 2 or not isinstance(coordinate[0], str) or not isinstance(coordinate[1], list):
            raise SeedFormatError(
                plan.path, f"{action.prefix}.coordinateReceptacleObjectId", "expected [ReceptacleType, [bounds...]]"
            )
        sources.append(
            PickupSource(
                object_id=action.get("objectId", str),
                receptacle_type=coordinate[0],
                receptacle_bounds=tuple(float(v) for v in coordinate[1]),
            )
        )
    return tuple(sources)


def _read_interactions(plan: _Fields) -> tuple[Interaction, ...]:
    interactions = []
    for low in plan.items("low_actions"):
        api = low.sub("api_action")
        action = api.get("action", str)
        if action not in INTERACTION_ACTIONS:
            continue
        receptacle = api.get("receptacleObjectId", str) if action == "PutObject" else ""
        interactions.append(Interaction(action=action, object_id=api.get("objectId", str), receptacle_id=receptacle))
    if not interactions:
        raise SeedFormatError(plan.path, f"{plan.prefix}.low_actions", "no interaction action in the trajectory")
    return tuple(interactions)


def read_seed_file(path: Path, root: Path | None = None, floorplans: Path | None = None) -> SeedTask:
    """Parse one `pp/ann_<r>.json` file; raise `SeedFormatError` naming the file and field on any problem."""
    path = Path(path)
    if not path.is_file():
        raise SeedFormatError(path, "", "file not found")
    try:
        raw = json.loads(path.read_text())
    except json.JSONDecodeError as exc:
        raise SeedFormatError(path, "", f"not valid JSON (line {exc.lineno}: {exc.msg})") from exc
    fields = _Fields(path, raw)
    repeat_idx = fields.get("repeat_idx", int)
    annotations = fields.sub("turk_annotations").items("anns")
    if not 0 <= repeat_idx < len(annotations):
        raise SeedFormatError(
            path, "turk_annotations.anns", f"repeat_idx {repeat_idx} but only {len(annotations)} annotations"
        )
    annotation = annotations[repeat_idx]
    plan = fields.sub("plan")
    root = root or alfred_dir()
    try:
        source_file = str(path.resolve().relative_to(root.resolve()))
    except ValueError:
        source_file = str(path)
    task_id = fields.get("task_id", str)
    task_name = path.parent.parent.parent.name
    return SeedTask(
        task_id=task_id,
        task_type=fields.get("task_type", str),
        task_name=task_name,
        repeat_idx=repeat_idx,
        source_file=source_file,
        pddl_params=_read_pddl(fields),
        scene=_read_scene(fields, floorplans or floorplans_dir()),
        instruction=annotation.get("task_desc", str).strip(),
        high_descs=tuple(d.strip() for d in annotation.get("high_descs", list)),
        pickup_sources=_read_pickup_sources(plan),
        interactions=_read_interactions(plan),
    )


def iter_seed_files(root: Path | None = None) -> Iterator[Path]:
    """Every `*/*/pp/ann_*.json` under the ALFRED folder, in sorted order (never file-system order)."""
    root = root or alfred_dir()
    if not root.is_dir():
        raise SeedFormatError(root, "", "ALFRED json_2.1.0 folder not found (set --alfred-dir or $TALKDEM_ALFRED_DIR)")
    yield from sorted(root.glob("*/*/pp/ann_*.json"))


def load_seed_pool(root: Path | None = None, floorplans: Path | None = None) -> list[SeedTask]:
    """Read every seed file under the ALFRED folder (sorted by path)."""
    root = root or alfred_dir()
    seeds = [read_seed_file(path, root, floorplans) for path in iter_seed_files(root)]
    if not seeds:
        raise SeedFormatError(root, "", "no pp/ann_*.json trajectory files found")
    return seeds
