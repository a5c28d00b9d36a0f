"""The initial state of a task, built deterministically from its stored scene and trajectory records.

Instances (which objects exist, with which AI2-THOR ids):
1. Receptacles with ids: `scene.openable_receptacles` (ALFRED's `-openable.json` lists every receptacle
   with its interaction pose, open or not: cabinets, counter tops, sink basins, ...).
2. Pickupable objects: one per `scene.object_poses` entry, id `Type|x|y|z` formatted `{v:+06.2f}` as
   AI2-THOR does. An id from the task's own trajectory that differs only by rounding (same type, every
   axis within 2 cm) renames that instance, so the trajectory and the state agree on ids.
3. Fixtures the poses do not list (faucets, lamps, stove burners, toilets, ...): every non-pickupable id
   that any seed trajectory of the same floor plan touches (fixtures do not move between ALFRED trials of
   a floor plan; the builder stores them with each task as `scene_fixture_ids`), plus the task's own
   trajectory ids. A sink basin with no known faucet within 1 m gets a
   synthetic one at its pose (`Faucet|synthetic|<sink id>`): every AI2-THOR sink has one, and the faucet
   cleans the basin nearest to it (ALFRED).
3c. A pan, pot or kettle standing on the stove top (near a known burner's height and within 0.6 m of it, but
   not on it) gets a burner of its own at its pose: AI2-THOR stoves have several burners, the trajectories
   name only those the expert used, and a burner holds one object.
4. A vocabulary type listed in `scene.scene_objects` that still has no instance gets one synthetic
   instance `Type|synthetic` at the agent's start (there is then only one, so its position cannot change
   which instance `find` picks).
5. Sinks and bathtubs are their basins (`Sink|..|SinkBasin`); the vocabulary names them by the parent.

Placement (which receptacle each object starts in):
A. An object the expert picks up starts in the receptacle its `pickup_sources` entry names: the instance
   of that type nearest to the recorded coordinate box (`receptacle_bounds` / 4 = x, z, y in metres).
   An empty source type means the object lay on no receptacle (the floor).
B. Any other pickupable starts in the nearest receptacle within `PROXIMITY_M` of its pose, if one is;
   a small object prefers a pickupable receptacle (plate, pan, mug, ...) within reach over a fixed one; a
   pickupable receptacle goes only in a fixed one, so containment stays acyclic; an object-specific receptacle
   (coffee machine, stove burner, toaster, ...) takes only its own types, one object at a time. This is
   what the trajectories rely on where they say nothing: a knife resting on a plate that the expert carries
   to the table, a potato lying in the sink basin that the expert slices in place.
C. Everything else sits on an unnamed open surface: reachable by `find`, in no receptacle.
D. Guard: no task's goal may hold at the start (ALFRED never samples such a trial). If rule B made the
   goal hold, rule-B placements of goal-relevant objects are undone, in id order, until it does not.
State: openable objects start closed except boxes and laptops (AI2-THOR's cardboard boxes have open flaps
and its laptops start open: ALFRED experts put objects in boxes and close laptops without opening them
first); toggleables off except `scene.object_toggles`; with
`scene.dirty_and_empty`, dirtyable objects start dirty. The agent starts at `scene.agent` (x, z).
"""

from __future__ import annotations

import math
from collections import defaultdict
from collections.abc import Iterable

from talkdem.seeds.records import SeedScene, SeedTask
from talkdem.sim.affordances import (
    BASIN_OF,
    DIRTYABLE_TYPES,
    MUST_BE_OPEN_TYPES,
    OBJECT_SPECIFIC_RECEPTACLES,
    SLICE_COUNT,
    STARTS_OPEN_TYPES,
    skill_type_of,
    type_flags,
    vocabulary_type,
)
from talkdem.sim.goals import check_goals, goal_targets
from talkdem.sim.state import ObjectSpec, SimState, whole_object_id
from talkdem.skills import categories

__all__ = ["PROXIMITY_M", "fixture_pool", "initial_state", "instance_id", "type_of_id"]

PROXIMITY_M = 0.3
"""Rule B: how close (metres, 3-D) an unplaced object must be to a receptacle's pose to start in it."""

_ROUNDING_M = 0.02
_FAUCET_REACH_M = 1.0
_BURNER_HEIGHT_M = 0.1
_STOVE_RADIUS_M = 0.6
_ON_BURNER_M = 0.1


def instance_id(object_type: str, x: float, y: float, z: float) -> str:
    """AI2-THOR's object id for a pose: `Apple|-02.31|+00.58|+01.20`."""
    return f"{object_type}|{x:+06.2f}|{y:+06.2f}|{z:+06.2f}"


def _normalise_id(object_id: str) -> str:
    """Slices map to their whole object; a bare `Sink|x|y|z` to its basin."""
    parts = object_id.split("|")
    if len(parts) >= 5 and parts[4] in BASIN_OF.values():
        return "|".join(parts[:5])
    whole = "|".join(parts[:4])
    if parts[0] in BASIN_OF and len(parts) == 4:
        return f"{whole}|{BASIN_OF[parts[0]]}"
    return whole


def type_of_id(object_id: str) -> str:
    """The AI2-THOR type an id names: `Sink|..|SinkBasin` -> `SinkBasin`, slices -> `AppleSliced`."""
    parts = object_id.split("|")
    if len(parts) >= 5:
        return parts[4].split("_")[0]
    return vocabulary_type(parts[0])


def _position_of_id(object_id: str) -> tuple[float, float, float]:
    parts = object_id.split("|")
    try:
        return (float(parts[1]), float(parts[2]), float(parts[3]))
    except (IndexError, ValueError):
        return (math.nan, math.nan, math.nan)


def _task_ids(task: SeedTask) -> list[str]:
    ids = [src.object_id for src in task.pickup_sources]
    for action in task.interactions:
        ids += [action.object_id] + ([action.receptacle_id] if action.receptacle_id else [])
    return [_normalise_id(i) for i in ids]


def fixture_pool(tasks: Iterable[SeedTask]) -> dict[str, frozenset[str]]:
    """Rule 3: the non-pickupable ids each floor plan's tasks touch (fixtures are the same in every trial)."""
    pool: dict[str, set[str]] = defaultdict(set)
    for task in tasks:
        for object_id in _task_ids(task):
            if not type_flags(type_of_id(object_id)).pickupable:
                pool[task.floor_plan].add(object_id)
    return {plan: frozenset(ids) for plan, ids in pool.items()}


def _spec(object_id: str, object_type: str, position: tuple[float, float, float]) -> ObjectSpec:
    flags = type_flags(object_type)
    slices: tuple[str, ...] = ()
    if flags.sliceable:
        slices = tuple(f"{object_id}|{object_type}Sliced_{i}" for i in range(SLICE_COUNT.get(object_type, 1)))
    return ObjectSpec(
        object_id=object_id,
        object_type=object_type,
        skill_type=skill_type_of(object_type),
        position=position,
        pickupable=flags.pickupable,
        receptacle=flags.receptacle,
        openable=flags.openable,
        toggleable=flags.toggleable,
        sliceable=flags.sliceable,
        must_be_open=object_type in MUST_BE_OPEN_TYPES,
        slices=slices,
    )


def _instances(task: SeedTask, pool: frozenset[str]) -> dict[str, ObjectSpec]:
    scene = task.scene
    specs: dict[str, ObjectSpec] = {}
    for receptacle in scene.openable_receptacles:
        rid = _normalise_id(receptacle.object_id)
        specs.setdefault(rid, _spec(rid, type_of_id(rid), _position_of_id(rid)))
    for pose in scene.object_poses:
        p = pose.position
        object_type = vocabulary_type(pose.object_type)
        oid = instance_id(object_type, p.x, p.y, p.z)
        specs.setdefault(oid, _spec(oid, object_type, (p.x, p.y, p.z)))
    for oid in [*_task_ids(task), *sorted(pool)]:
        if oid in specs:
            continue
        object_type, position = type_of_id(oid), _position_of_id(oid)
        if type_flags(object_type).pickupable:
            twin = _rounding_twin(specs, object_type, position)
            if twin is not None:
                del specs[twin]
                position = _position_of_pose(scene, object_type, position)
        specs[oid] = _spec(oid, object_type, position)
    _add_missing_faucets(specs)
    _add_missing_burners(specs)
    known_types = {spec.skill_type for spec in specs.values()}
    findable = set(categories().findable)
    for raw_type in scene.scene_objects:
        object_type = vocabulary_type(raw_type)
        if skill_type_of(object_type) in findable and skill_type_of(object_type) not in known_types:
            object_type = BASIN_OF.get(object_type, object_type)
            oid = f"{object_type}|synthetic"
            specs[oid] = _spec(oid, object_type, (scene.agent.x, 0.0, scene.agent.z))
            known_types.add(skill_type_of(object_type))
    for spec in list(specs.values()):
        for slice_id in spec.slices:
            specs[slice_id] = _spec(slice_id, f"{spec.object_type}Sliced", spec.position)
    return specs


def _add_missing_faucets(specs: dict[str, ObjectSpec]) -> None:
    """Rule 3b: every AI2-THOR sink has a faucet; a basin with no known faucet within 1 m gets one at its pose."""
    faucets = [s.position for s in specs.values() if s.object_type == "Faucet"]
    for oid, spec in sorted(specs.items()):
        if spec.object_type != "SinkBasin":
            continue
        if not any(math.dist(f, spec.position) <= _FAUCET_REACH_M for f in faucets):
            faucet_id = f"Faucet|synthetic|{whole_object_id(oid)}"
            specs[faucet_id] = _spec(faucet_id, "Faucet", spec.position)


def _add_missing_burners(specs: dict[str, ObjectSpec]) -> None:
    """Rule 3c: a pan, pot or kettle standing on the stove top stands on a burner of its own.

    The trajectories name only the burners an expert used, but AI2-THOR stoves have several and a burner holds
    one object (`ObjectSpecificReceptacle`). A stove-top object (within `_BURNER_HEIGHT_M` of a known burner's
    height and `_STOVE_RADIUS_M` of it on the floor plane, but not on it) gets a burner at its pose.
    """
    burners = [s.position for s in specs.values() if s.object_type == "StoveBurner"]
    if not burners:
        return
    for _, spec in sorted(specs.items()):
        if spec.object_type not in OBJECT_SPECIFIC_RECEPTACLES["StoveBurner"]:
            continue
        x, y, z = spec.position
        near = [
            b
            for b in burners
            if abs(b[1] - y) <= _BURNER_HEIGHT_M and math.dist((b[0], b[2]), (x, z)) <= _STOVE_RADIUS_M
        ]
        if near and all(math.dist((b[0], b[2]), (x, z)) > _ON_BURNER_M for b in near):
            position = (x, near[0][1], z)
            burner_id = instance_id("StoveBurner", *position)
            specs.setdefault(burner_id, _spec(burner_id, "StoveBurner", position))
            burners.append(position)


def _rounding_twin(specs: dict[str, ObjectSpec], object_type: str, position: tuple[float, float, float]) -> str | None:
    for oid, spec in specs.items():
        if spec.object_type == object_type and all(
            abs(a - b) <= _ROUNDING_M for a, b in zip(spec.position, position, strict=True)
        ):
            return oid
    return None


def _position_of_pose(
    scene: SeedScene, object_type: str, near: tuple[float, float, float]
) -> tuple[float, float, float]:
    best = min(
        (p.position for p in scene.object_poses if vocabulary_type(p.object_type) == object_type),
        key=lambda p: math.dist((p.x, p.y, p.z), near),
    )
    return (best.x, best.y, best.z)


def _nearest(specs: dict[str, ObjectSpec], candidates: Iterable[str], point: tuple[float, float, float]) -> str | None:
    ranked = sorted(candidates, key=lambda r: (math.dist(specs[r].position, point), r))
    return ranked[0] if ranked else None


def _placements(task: SeedTask, specs: dict[str, ObjectSpec]) -> tuple[dict[str, str], list[str]]:
    """Rules A-C: the starting receptacle of each object, and which of them rule B inferred."""
    parents: dict[str, str] = {}
    sourced: set[str] = set()
    for src in task.pickup_sources:
        oid = _normalise_id(src.object_id)
        if oid in sourced or oid not in specs:
            continue
        sourced.add(oid)
        if not src.receptacle_type:
            continue
        rtype = vocabulary_type(src.receptacle_type)
        b = src.receptacle_bounds
        point = (b[0] / 4, b[4] / 4, b[2] / 4) if len(b) >= 6 else specs[oid].position
        receptacle = _nearest(specs, (r for r, s in specs.items() if s.object_type == rtype), point)
        if receptacle is None:
            receptacle = instance_id(rtype, *point)
            specs[receptacle] = _spec(receptacle, rtype, point)
        parents[oid] = receptacle
    fixed = [r for r, s in specs.items() if s.receptacle and not s.pickupable and "Sliced" not in s.object_type]
    movable = [r for r, s in specs.items() if s.receptacle and s.pickupable]
    inferred: list[str] = []
    occupied = set(parents.values())
    for oid, spec in sorted(specs.items()):
        if not spec.pickupable or oid in sourced or "Sliced" in spec.object_type or "synthetic" in oid:
            continue
        receptacle = None
        for candidates in ([] if spec.receptacle else movable, fixed):
            near = [
                r
                for r in candidates
                if r != oid
                and math.dist(specs[r].position, spec.position) <= PROXIMITY_M
                and _can_hold(specs[r].object_type, spec.object_type, r in occupied)
            ]
            receptacle = _nearest(specs, near, spec.position)
            if receptacle is not None:
                break
        if receptacle is not None:
            parents[oid] = receptacle
            occupied.add(receptacle)
            inferred.append(oid)
    return parents, inferred


def _can_hold(receptacle_type: str, object_type: str, occupied: bool) -> bool:
    """An object-specific receptacle holds one object of its types; any other receptacle holds anything."""
    allowed = OBJECT_SPECIFIC_RECEPTACLES.get(receptacle_type)
    return allowed is None or (object_type in allowed and not occupied)


def _build(task: SeedTask, pool: frozenset[str]) -> SimState:
    specs = _instances(task, pool)
    parents, inferred = _placements(task, specs)
    by_type: dict[str, list[str]] = defaultdict(list)
    for oid in sorted(specs):
        by_type[specs[oid].skill_type].append(oid)
    scene = task.scene
    toggled_types = {vocabulary_type(t.object_type) for t in scene.object_toggles if t.is_on}
    state = SimState(
        specs=specs,
        by_skill_type={t: tuple(ids) for t, ids in by_type.items()},
        present={oid for oid, spec in specs.items() if "Sliced" not in spec.object_type},
        parent={},
        contents={},
        is_open={oid: spec.object_type in STARTS_OPEN_TYPES for oid, spec in specs.items() if spec.openable},
        is_toggled={oid: spec.object_type in toggled_types for oid, spec in specs.items() if spec.toggleable},
        dirty={oid for oid, s in specs.items() if scene.dirty_and_empty and s.object_type in DIRTYABLE_TYPES},
        sliced=set(),
        moved={},
        agent=(scene.agent.x, scene.agent.z),
    )
    for oid in sorted(parents):
        state.attach(oid, parents[oid])
    _undo_goal_at_start(task, state, inferred)
    return state


def _undo_goal_at_start(task: SeedTask, state: SimState, inferred: list[str]) -> None:
    """Rule D."""
    targets = goal_targets(task.pddl_params)
    names = [n for n in (targets.object, targets.mrecep) if n]
    for oid in inferred:
        if not check_goals(task.task_type, task.pddl_params, state).success:
            return
        if any(name in oid for name in names):
            state.detach(oid)


_PROTOTYPES: dict[str, tuple[SeedScene, SimState]] = {}


def initial_state(task: SeedTask, pool: dict[str, frozenset[str]] | None = None) -> SimState:
    """A fresh copy of the task's initial state (built once per task, then copied; see module docstring)."""
    cached = _PROTOTYPES.get(task.task_id)
    if cached is None or (cached[0] is not task.scene and cached[0] != task.scene) or pool is not None:
        if pool is not None:
            floor_pool = pool.get(task.floor_plan, frozenset())
        else:
            floor_pool = frozenset(getattr(task, "scene_fixture_ids", ()))
        cached = (task.scene, _build(task, floor_pool))
        if pool is None:
            _PROTOTYPES[task.task_id] = cached
    return cached[1].copy()
