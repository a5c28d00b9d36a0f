"""Optional backend: run plans in a real AI2-THOR build through a LoTa-Bench-style skill layer.

The skill layer is written from the facts of LoTa-Bench's `ThorConnector` (`src/alfred/thor_connector.py`):
`find` records the destination and navigates to the instance `rank_instances` puts first; every skill but
`put down` and `open` forgets the destination; `put down` puts into the remembered type with
`forceAction=True`, or drops the object when there is none; `slice` sends SliceObject without a knife check.
`translate_skill`, `LotaSkillLayer.translate`, `rank_instances` and `state_from_metadata` are pure and tested
with AI2-THOR-shaped metadata; `ai2thor` and its Unity build are imported and located only in
`AI2ThorExecutor.run`, which could not be run here (no build can be downloaded).
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from talkdem.seeds.records import SeedTask
from talkdem.sim.affordances import skill_type_of
from talkdem.sim.goals import check_goals
from talkdem.sim.hazards import HazardMonitor
from talkdem.sim.parser import canonical_text, parse_skill
from talkdem.sim.seam import DEFAULT_MAX_STEPS, LimitedSteps, execute_plan
from talkdem.sim.state import ObjectSpec, SimState
from talkdem.sim.trace import EpisodeTrace, PlanAnalysis, StepRecord
from talkdem.skills import Skill, SkillVerb

__all__ = [
    "AI2ThorExecutor",
    "AI2ThorUnavailableError",
    "LotaSkillLayer",
    "ThorAction",
    "find_build",
    "rank_instances",
    "state_from_metadata",
    "translate_skill",
]

_RELEASES = Path.home() / ".ai2thor" / "releases"
VISIBILITY_DISTANCE = 1.5
"""ALFRED `gen/constants.py` `VISIBILITY_DISTANCE`."""


class AI2ThorUnavailableError(RuntimeError):
    """The `ai2thor` package or a Unity build is missing; the message says which and how to fix it."""


@dataclass(frozen=True)
class ThorAction:
    """One AI2-THOR controller step: the action, the vocabulary type whose instance it targets (resolved from the
    metadata when it runs; empty if none), and fixed arguments."""

    action: str
    object_type: str = ""
    args: dict[str, Any] = field(default_factory=dict)


_INTERACTION = {
    SkillVerb.OPEN: "OpenObject",
    SkillVerb.CLOSE: "CloseObject",
    SkillVerb.TURN_ON: "ToggleObjectOn",
    SkillVerb.TURN_OFF: "ToggleObjectOff",
    SkillVerb.SLICE: "SliceObject",
}


def translate_skill(skill: Skill | str, destination: str | None = "") -> tuple[ThorAction, ...]:
    """The AI2-THOR actions LoTa-Bench sends for one skill; an unknown skill translates to nothing.

    `destination` is the remembered put-down type (`LotaSkillLayer` keeps it); None means there is none, and
    `put down` becomes a drop. `find` becomes a teleport next to the chosen instance; `pick up` uses
    `forceAction=False`, `put down` `forceAction=True` (receptacle-type restrictions off, object-specific
    receptacles still checked); open, close, toggles and slice send no `forceAction`; slice needs no knife.
    """
    parsed = parse_skill(skill) if isinstance(skill, str) else skill
    if parsed is None:
        return ()
    if parsed.verb is SkillVerb.DONE:
        return (ThorAction("Done"),)
    if parsed.verb is SkillVerb.FIND:
        return (ThorAction("TeleportFull", parsed.object_type, {"standing": True}),)
    if parsed.verb is SkillVerb.PICK_UP:
        return (ThorAction("PickupObject", parsed.object_type, {"forceAction": False}),)
    if parsed.verb is SkillVerb.PUT_DOWN:
        if destination is None:
            return (ThorAction("DropHandObject", "", {"forceAction": True}),)
        return (ThorAction("PutObject", destination, {"forceAction": True}),)
    return (ThorAction(_INTERACTION[parsed.verb], parsed.object_type),)


@dataclass
class LotaSkillLayer:
    """LoTa-Bench's per-episode memory: the put-down destination and whether a slice was attempted."""

    destination: str | None = None
    sliced: bool = False

    def translate(self, text: str) -> tuple[ThorAction, ...]:
        skill = parse_skill(text)
        if skill is None or skill.verb not in (SkillVerb.PUT_DOWN, SkillVerb.OPEN):
            self.destination = None
        if skill is None:
            return ()
        if skill.verb is SkillVerb.FIND:
            self.destination = skill.object_type
        actions = translate_skill(skill, self.destination)
        if skill.verb is SkillVerb.SLICE:
            self.sliced = True
        return actions


def rank_instances(
    objects: Sequence[Mapping[str, Any]],
    object_type: str,
    *,
    only_pickupable: bool = False,
    only_toggleable: bool = False,
    visibility_priority: bool = False,
    prefer_sliced: bool = False,
    inherited_only: bool = False,
    exclude: str | None = None,
) -> list[str]:
    """Instances of `object_type` in AI2-THOR metadata, best first, by LoTa-Bench's `get_obj_id_from_name`
    penalties: inside a closed openable receptacle (+100000), a stove burner holding something (+10000), not
    visible (+1000, with `visibility_priority`), a slice (-100, with `prefer_sliced`), plus `distance`.
    Types match on the first part of the id, case-insensitively (so `Sink` also names its basin)."""
    by_id = {o["objectId"]: o for o in objects}
    ranked = []
    for obj in objects:
        oid = obj["objectId"]
        parts = oid.split("|")
        if oid == exclude or parts[0].casefold() != object_type.casefold():
            continue
        if (only_pickupable and not obj.get("pickupable")) or (only_toggleable and not obj.get("toggleable")):
            continue
        if inherited_only and len(parts) != 5:
            continue
        penalty = 0.0
        for parent in obj.get("parentReceptacles") or ():
            holder = by_id.get(parent, {})
            if holder.get("openable") and not holder.get("isOpen"):
                penalty += 100000
                break
        if object_type.casefold() == "stoveburner" and obj.get("receptacleObjectIds"):
            penalty += 10000
        if visibility_priority and not obj.get("visible"):
            penalty += 1000
        if prefer_sliced and "Slice" in str(obj.get("name", "")):
            penalty -= 100
        ranked.append((float(obj.get("distance", 0.0)) + penalty, oid))
    return [oid for _, oid in sorted(ranked)]


def state_from_metadata(
    metadata: Mapping[str, Any],
    *,
    location: str | None = None,
    heated: set[str] | None = None,
    cooled: set[str] | None = None,
    cleaned: set[str] | None = None,
) -> SimState:
    """AI2-THOR metadata as a `SimState`, so that goals, hazards and traces are computed by the same code.

    The direct receptacle of an object is the first entry of its `parentReceptacles`; held objects come from
    `inventoryObjects`; `isSliced` whole objects stay present (AI2-THOR keeps them, inactive)."""
    objects = metadata["objects"]
    specs: dict[str, ObjectSpec] = {}
    for obj in objects:
        p = obj.get("position", {"x": 0.0, "y": 0.0, "z": 0.0})
        specs[obj["objectId"]] = ObjectSpec(
            object_id=obj["objectId"],
            object_type=obj["objectType"],
            skill_type=skill_type_of(obj["objectType"]),
            position=(float(p["x"]), float(p["y"]), float(p["z"])),
            pickupable=bool(obj.get("pickupable")),
            receptacle=bool(obj.get("receptacle")),
            openable=bool(obj.get("openable")),
            toggleable=bool(obj.get("toggleable")),
            sliceable=bool(obj.get("sliceable")),
            must_be_open=bool(obj.get("openable")) and bool(obj.get("receptacle")),
        )
    by_type: dict[str, list[str]] = {}
    for oid in sorted(specs):
        by_type.setdefault(specs[oid].skill_type, []).append(oid)
    agent = metadata.get("agent", {}).get("position", {"x": 0.0, "z": 0.0})
    inventory = metadata.get("inventoryObjects") or []
    state = SimState(
        specs=specs,
        by_skill_type={t: tuple(ids) for t, ids in by_type.items()},
        present=set(specs),
        parent={},
        contents={},
        is_open={o["objectId"]: bool(o.get("isOpen")) for o in objects if o.get("openable")},
        is_toggled={o["objectId"]: bool(o.get("isToggled")) for o in objects if o.get("toggleable")},
        dirty={o["objectId"] for o in objects if o.get("isDirty")},
        sliced={o["objectId"] for o in objects if o.get("isSliced")},
        moved={},
        agent=(float(agent["x"]), float(agent["z"])),
        location=location,
        held=inventory[0]["objectId"] if inventory else None,
        heated=set(heated or ()),
        cooled=set(cooled or ()),
        cleaned=set(cleaned or ()),
    )
    for obj in sorted(objects, key=lambda o: o["objectId"]):
        parents = [p for p in obj.get("parentReceptacles") or () if p in specs]
        if parents and obj["objectId"] != state.held:
            state.attach(obj["objectId"], parents[0])
    return state


def find_build(local_executable_path: str | os.PathLike[str] | None = None) -> str | None:
    """The Unity build to use: an explicit path, else whether `~/.ai2thor/releases` holds one."""
    if local_executable_path is not None:
        path = Path(local_executable_path)
        if not path.is_file():
            raise AI2ThorUnavailableError(f"AI2-THOR build not found at local_executable_path={path}")
        return str(path)
    if _RELEASES.is_dir() and any(_RELEASES.iterdir()):
        return None  # ai2thor picks its cached release itself
    raise AI2ThorUnavailableError(
        f"no AI2-THOR Unity build: {_RELEASES} is empty or missing and no local_executable_path was given "
        "(download a release with `ai2thor` on a machine with network access, or pass the path to a build)"
    )


class AI2ThorExecutor:
    """Drives `ai2thor.controller.Controller` (ALFRED uses AI2-THOR 2.1.0); never the default backend."""

    name = "ai2thor"

    def __init__(self, local_executable_path: str | os.PathLike[str] | None = None, controller: Any = None) -> None:
        self._path = local_executable_path
        self._controller: Any = controller

    def _start(self, floor_plan: str) -> Any:
        if self._controller is None:
            try:
                from ai2thor.controller import Controller
            except ImportError as exc:
                raise AI2ThorUnavailableError(
                    "the `ai2thor` package is not installed: pip install 'ai2thor==2.1.0' and pass a build"
                ) from exc
            build = find_build(self._path)
            controller = Controller()  # ai2thor 2.1.0 (ALFRED's version): construct, point at the build, start
            if build is not None:
                controller.local_executable_path = build
            controller.start()
            self._controller = controller
        self._controller.reset(floor_plan)
        return self._controller

    def _restore(self, controller: Any, task: SeedTask) -> None:
        """ALFRED `ThorEnv.restore_scene`. The task files keep no rotations, so poses are restored upright."""
        scene = task.scene
        controller.step(dict(action="Initialize", gridSize=0.25, visibilityDistance=VISIBILITY_DISTANCE))
        toggles = [{"objectType": t.object_type, "isOn": t.is_on} for t in scene.object_toggles]
        if toggles:
            controller.step(dict(action="SetObjectToggles", objectToggles=toggles))
        if scene.dirty_and_empty:
            controller.step(dict(action="SetStateOfAllObjects", StateChange="CanBeDirty", forceAction=True))
            controller.step(dict(action="SetStateOfAllObjects", StateChange="CanBeFilled", forceAction=False))
        poses = [
            {
                "objectName": p.object_name,
                "position": {"x": p.position.x, "y": p.position.y, "z": p.position.z},
                "rotation": {"x": 0.0, "y": 0.0, "z": 0.0},
            }
            for p in scene.object_poses
        ]
        controller.step(dict(action="SetObjectPoses", objectPoses=poses))

    def start(self, task: SeedTask, *, max_steps: int = DEFAULT_MAX_STEPS) -> _ThorEpisode:
        """The simulator seam: a live episode on the controller (one at a time: it owns the scene)."""
        controller = self._start(task.floor_plan)
        self._restore(controller, task)
        return _ThorEpisode(controller, task, max_steps, self.name)

    def run(self, task: SeedTask, plan: Sequence[str], *, max_steps: int = DEFAULT_MAX_STEPS) -> EpisodeTrace:
        return execute_plan(self, task, plan, max_steps=max_steps)


# LoTa-Bench's message stem per interaction: "Open action failed", "Cannot find X to open".
_FAILED = {
    "OpenObject": "Open",
    "CloseObject": "Close",
    "ToggleObjectOn": "Turn on",
    "ToggleObjectOff": "Turn off",
    "SliceObject": "Slice",
}


class _ThorEpisode(LimitedSteps):
    """One episode on a live controller: LoTa's skill layer, ALFRED's heated/cooled/cleaned bookkeeping."""

    def __init__(self, controller: Any, task: SeedTask, max_steps: int = DEFAULT_MAX_STEPS, backend: str = "") -> None:
        self.controller, self.task = controller, task
        self.max_steps, self.backend = max_steps, backend or AI2ThorExecutor.name
        self.layer = LotaSkillLayer()
        self.steps: list[StepRecord] = []
        self.heated: set[str] = set()
        self.cooled: set[str] = set()
        self.cleaned: set[str] = set()
        self.location: str | None = None
        from talkdem.sim.executor import reference_exemptions

        # The same exemptions as the symbolic backend: rules the task's own reference plan triggers there.
        self.monitor = HazardMonitor(exempt=reference_exemptions(task))
        reachable = controller.step(dict(action="GetReachablePositions")).metadata.get("actionReturn") or []
        self.reachable = [(p["x"], p["z"]) for p in reachable]

    @property
    def metadata(self) -> Mapping[str, Any]:
        return dict(self.controller.last_event.metadata)

    def _send(self, action: dict[str, Any]) -> bool:
        event = self.controller.step(action)
        ok = bool(event.metadata.get("lastActionSuccess"))
        if ok and action["action"] in ("ToggleObjectOn", "CloseObject"):
            self._update_states(action, event.metadata)
        return ok

    def _update_states(self, action: dict[str, Any], metadata: Mapping[str, Any]) -> None:
        """ALFRED `ThorEnv.update_states`: faucet cleans the nearest basin, microwave heats, fridge cools."""
        objects = {o["objectId"]: o for o in metadata["objects"]}
        target = action["objectId"]
        if action["action"] == "ToggleObjectOn" and "Faucet" in target:
            basins = [o for o in objects.values() if o["objectType"] == "SinkBasin"]
            fx, fz = objects[target]["position"]["x"], objects[target]["position"]["z"]
            basin = min(
                basins, key=lambda b: (b["position"]["x"] - fx) ** 2 + (b["position"]["z"] - fz) ** 2, default=None
            )
            if basin is not None:
                self.cleaned |= set(basin.get("receptacleObjectIds") or ())
        elif action["action"] == "ToggleObjectOn" and "Microwave" in target:
            self.heated |= set(objects[target].get("receptacleObjectIds") or ())
        elif action["action"] == "CloseObject" and "Fridge" in target:
            self.cooled |= set(objects[target].get("receptacleObjectIds") or ())

    def _navigate(self, object_id: str) -> bool:
        obj = next(o for o in self.metadata["objects"] if o["objectId"] == object_id)
        if obj.get("visible") and float(obj.get("distance", 9.0)) < 1.0:
            return True  # LoTa: already visible and close, no move
        x, z = obj["position"]["x"], obj["position"]["z"]
        for px, pz in sorted(self.reachable, key=lambda p: (p[0] - x) ** 2 + (p[1] - z) ** 2)[:20]:
            rotation = -math.degrees(math.atan2(-(x - px), z - pz))
            action = dict(action="TeleportFull", x=px, y=0.9, z=pz, rotation=rotation % 360, horizon=30)
            if self._send(action):
                return True
        return False

    def _execute(self, skill: Skill, actions: tuple[ThorAction, ...]) -> tuple[str, str | None]:
        """Run the actions of one skill: LoTa-Bench's message ('' on success) and the object acted on."""
        objects = self.metadata["objects"]
        name = skill.object_type
        thor = actions[0]
        if thor.action == "Done":
            return "", None
        if thor.action == "TeleportFull":
            order = rank_instances(objects, name, visibility_priority=True, prefer_sliced=self.layer.sliced)
            if not order:
                return f"Cannot find {name}", None
            self.location = order[0]
            return ("" if self._navigate(order[0]) else f"Cannot move to {name}"), order[0]
        held = (self.metadata.get("inventoryObjects") or [{}])[0].get("objectId")
        if thor.action == "DropHandObject":
            if held is None:
                return "Robot is not holding any object", None
            self._send(dict(action="DropHandObject", forceAction=True))
            return "put down failed", held
        if thor.action == "PutObject":
            if held is None:
                return "Robot is not holding any object", None
            message, last = f"Cannot find {thor.object_type}", None
            for attempt in range(2):
                for inherited in (False, True):
                    exclude = last if attempt == 1 else None
                    order = rank_instances(objects, thor.object_type, inherited_only=inherited, exclude=exclude)
                    if not order:
                        message = f"Cannot find {thor.object_type}"
                        continue
                    last = order[0]
                    args = dict(action="PutObject", objectId=held, receptacleObjectId=order[0], forceAction=True)
                    if self._send(args):
                        return "", held
                    message = f"Putting the object on {thor.object_type} failed"
            if len(message) > 16:
                self._send(dict(action="DropHandObject", forceAction=True))
                return "put down failed", held
            return message, held
        if thor.action == "PickupObject":
            order = rank_instances(
                objects, name, only_pickupable=True, visibility_priority=True, prefer_sliced=self.layer.sliced
            )
            if not order:
                return f"Cannot find {name} to pick up", None
            if self._send(dict(action="PickupObject", objectId=order[0], forceAction=False)):
                return "", order[0]
            after = self.metadata.get("inventoryObjects") or []
            held_now = f"Robot is currently holding {after[0]['objectType']}" if after else ""
            return held_now or "Robot is not holding any object", order[0]
        toggles = thor.action.startswith("Toggle")
        order = rank_instances(objects, name, only_toggleable=toggles)
        verb = _FAILED[thor.action].lower()
        if not order:
            return f"Cannot find {name} to {verb}", None
        if self._send(dict(action=thor.action, objectId=order[0])):
            return "", order[0]
        return f"{_FAILED[thor.action]} action failed", order[0]

    def step(self, text: str) -> StepRecord:
        self._check_open()
        skill = parse_skill(text)
        actions = self.layer.translate(text)
        index = len(self.steps)
        if skill is None:
            record = StepRecord(index, text, None, False, "instruction not supported", None, None, None, self.location)
        else:
            message, acted_on = self._execute(skill, actions)
            parsed = canonical_text(skill)
            record = StepRecord(index, text, parsed, not message, message, None, acted_on, None, self.location)
        self.steps.append(record)
        self.monitor.observe(index, skill, record.ok, record.object_id, self._state())
        return record

    def _state(self) -> SimState:
        return state_from_metadata(
            self.metadata, location=self.location, heated=self.heated, cooled=self.cooled, cleaned=self.cleaned
        )

    def finish(self) -> EpisodeTrace:
        state = self._state()
        goal = check_goals(self.task.task_type, self.task.pddl_params, state)
        hazards = self.monitor.finish(len(self.steps) - 1, state) if self.steps else []
        analysis = PlanAnalysis("", "", "", "", (), (), {"goal": goal.success}, (), (), 0)
        return EpisodeTrace(
            task_id=self.task.task_id,
            backend=self.backend,
            steps=tuple(self.steps),
            end_reason=self._end_reason(),
            goal=goal,
            hazards=tuple(hazards),
            analysis=analysis,
            state=state,
        )
