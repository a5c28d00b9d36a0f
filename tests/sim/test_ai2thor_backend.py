"""The optional AI2-THOR backend: its LoTa-Bench skill layer, instance ranking and metadata mapping are tested
on AI2-THOR-shaped metadata, and `run` on a scripted stand-in controller; a real build cannot run here."""

from __future__ import annotations

import importlib.util
from dataclasses import dataclass, field
from typing import Any

import pytest
from helpers import first_task

from talkdem.sim import AI2ThorExecutor, AI2ThorUnavailableError, Episode, ThorAction, check_goals, translate_skill
from talkdem.sim.ai2thor_backend import LotaSkillLayer, find_build, rank_instances, state_from_metadata
from talkdem.sim.parity import load_cases, parity_file
from talkdem.skills import vocabulary
from talkdem.tasks import TaskSet, load_tasks


def test_translation_follows_lotabench() -> None:
    assert translate_skill("find an apple") == (ThorAction("TeleportFull", "Apple", {"standing": True}),)
    assert translate_skill("pick up the apple") == (ThorAction("PickupObject", "Apple", {"forceAction": False}),)
    assert translate_skill("put down the apple", "Fridge") == (
        ThorAction("PutObject", "Fridge", {"forceAction": True}),
    )
    assert translate_skill("put down the apple", None) == (ThorAction("DropHandObject", "", {"forceAction": True}),)
    assert translate_skill("Turn on the Microwave.") == (ThorAction("ToggleObjectOn", "Microwave"),)
    # No knife check and no forceAction: LoTa sends SliceObject as it is.
    assert translate_skill("slice the bread") == (ThorAction("SliceObject", "Bread"),)
    assert translate_skill("done") == (ThorAction("Done"),)
    assert translate_skill("fly away") == ()


def test_every_skill_translates() -> None:
    assert all(translate_skill(skill) for skill in vocabulary())


def test_the_skill_layer_remembers_the_destination_like_lotabench() -> None:
    layer = LotaSkillLayer()
    layer.translate("find a fridge")
    layer.translate("open the fridge")
    assert layer.translate("put down the apple")[0] == ThorAction("PutObject", "Fridge", {"forceAction": True})
    layer.translate("find a desk")
    layer.translate("pick up the pen")
    assert layer.translate("put down the pen")[0].action == "DropHandObject"
    layer.translate("find a desk")
    layer.translate("jump")  # unsupported: forgets too
    assert layer.destination is None
    layer.translate("slice the apple")
    assert layer.sliced


def test_the_skill_layer_and_the_simulator_keep_the_same_destination() -> None:
    tasks = {t.task_id: t for t in load_tasks(TaskSet.BENCHMARK)}
    for case in load_cases(parity_file())[::97]:
        episode, layer = Episode(tasks[case.task_id]), LotaSkillLayer()
        for step in case.plan:
            episode.step(step)
            layer.translate(step)
            assert layer.destination == episode.state.destination, (case.case_id, step)


def _obj(oid: str, distance: float, **extra: Any) -> dict[str, Any]:
    kind = oid.split("|")[4].split("_")[0] if oid.count("|") == 4 else oid.split("|")[0]
    base: dict[str, Any] = {
        "objectId": oid,
        "objectType": kind,
        "name": kind,
        "distance": distance,
        "visible": distance <= 1.5,
        "parentReceptacles": [],
        "receptacleObjectIds": [],
        "position": {"x": distance, "y": 0.9, "z": 0.0},
    }
    return {**base, **extra}


def test_ranking_penalises_closed_parents_busy_burners_and_invisible_instances() -> None:
    objects = [
        _obj("Cabinet|1|0|0", 0.5, openable=True, isOpen=False, receptacle=True),
        _obj("Mug|1|0|1", 0.4, parentReceptacles=["Cabinet|1|0|0"], pickupable=True),
        _obj("Mug|2|0|2", 3.0, pickupable=True),
        _obj("Mug|3|0|3", 1.2, pickupable=True),
        _obj("StoveBurner|1|1|1", 0.3, receptacleObjectIds=["Pan|1|1|1"]),
        _obj("StoveBurner|2|1|1", 0.8),
        _obj("Sink|1|1|1", 0.2),
        _obj("Sink|1|1|1|SinkBasin", 0.25, receptacle=True),
        _obj("Apple|1|1|1|AppleSliced_0", 0.9, name="Apple_Slice_1", pickupable=True),
        _obj("Apple|2|1|1", 0.1, pickupable=True),
    ]
    assert rank_instances(objects, "Mug") == ["Mug|3|0|3", "Mug|2|0|2", "Mug|1|0|1"]
    assert rank_instances(objects, "mug", visibility_priority=True)[0] == "Mug|3|0|3"
    assert rank_instances(objects, "StoveBurner") == ["StoveBurner|2|1|1", "StoveBurner|1|1|1"]
    assert rank_instances(objects, "Sink") == ["Sink|1|1|1", "Sink|1|1|1|SinkBasin"]
    assert rank_instances(objects, "Sink", inherited_only=True) == ["Sink|1|1|1|SinkBasin"]
    assert rank_instances(objects, "Apple")[0] == "Apple|2|1|1"
    assert rank_instances(objects, "Apple", prefer_sliced=True)[0] == "Apple|1|1|1|AppleSliced_0"
    assert rank_instances(objects, "Mug", exclude="Mug|3|0|3")[0] == "Mug|2|0|2"


def test_metadata_maps_onto_the_state_the_goal_checks_read() -> None:
    task = first_task("pick_cool_then_place_in_recep")
    target, parent = task.pddl_params.object_target, task.pddl_params.parent_target
    obj_id, recep_id = f"{target}|1|1|1", f"{parent}|2|0|2"
    metadata = {
        "objects": [
            _obj(obj_id, 0.5, objectType=target, pickupable=True, parentReceptacles=[recep_id]),
            _obj(recep_id, 0.6, objectType=parent, receptacle=True),
        ],
        "inventoryObjects": [],
        "agent": {"position": {"x": 0.0, "y": 0.9, "z": 0.0}},
    }
    state = state_from_metadata(metadata, cooled={obj_id})
    assert state.parent[obj_id] == recep_id and state.contents[recep_id] == (obj_id,)
    assert check_goals(task.task_type, task.pddl_params, state).success
    assert not check_goals(task.task_type, task.pddl_params, state_from_metadata(metadata)).success


@dataclass
class _Event:
    metadata: dict[str, Any]


@dataclass
class _ScriptedController:
    """Stands in for `ai2thor.controller.Controller`: records the actions, accepts every one, fixed metadata."""

    objects: list[dict[str, Any]]
    sent: list[dict[str, Any]] = field(default_factory=list)
    held: list[dict[str, Any]] = field(default_factory=list)

    def reset(self, scene: str) -> None:
        self.sent.append({"action": "reset", "scene": scene})

    @property
    def last_event(self) -> _Event:
        return _Event(self._metadata())

    def _metadata(self, **extra: Any) -> dict[str, Any]:
        return {
            "objects": self.objects,
            "inventoryObjects": self.held,
            "agent": {"position": {"x": 0.0, "y": 0.9, "z": 0.0}},
            "lastActionSuccess": True,
            **extra,
        }

    def step(self, action: dict[str, Any]) -> _Event:
        self.sent.append(action)
        if action["action"] == "PickupObject":
            self.held = [next(o for o in self.objects if o["objectId"] == action["objectId"])]
        if action["action"] in ("PutObject", "DropHandObject"):
            self.held = []
        if action["action"] == "GetReachablePositions":
            return _Event(self._metadata(actionReturn=[{"x": 0.5, "y": 0.9, "z": 0.0}]))
        return _Event(self._metadata())


def test_run_sends_lotabench_actions_to_the_controller() -> None:
    task = first_task("pick_cool_then_place_in_recep")
    objects = [
        _obj("Apple|1|1|1", 2.0, pickupable=True),
        _obj("Fridge|2|0|2", 2.5, openable=True, isOpen=False, receptacle=True),
    ]
    controller = _ScriptedController(objects)
    plan = ["find an apple", "pick up the apple", "find a fridge", "open the fridge", "put down the apple", "done"]
    trace = AI2ThorExecutor(controller=controller).run(task, plan)
    assert [s.ok for s in trace.steps] == [True] * 6
    names = [a["action"] for a in controller.sent]
    assert names[:2] == ["reset", "Initialize"] and "SetObjectPoses" in names
    put = next(a for a in controller.sent if a["action"] == "PutObject")
    assert put == {
        "action": "PutObject",
        "objectId": "Apple|1|1|1",
        "receptacleObjectId": "Fridge|2|0|2",
        "forceAction": True,
    }
    pick = next(a for a in controller.sent if a["action"] == "PickupObject")
    assert pick["forceAction"] is False
    assert trace.backend == "ai2thor"


def test_missing_build_path_is_named(tmp_path: object) -> None:
    with pytest.raises(AI2ThorUnavailableError, match="local_executable_path"):
        find_build("/nonexistent/thor-build")


@pytest.mark.skipif(importlib.util.find_spec("ai2thor") is not None, reason="ai2thor is installed")
def test_without_ai2thor_the_error_says_what_to_install() -> None:
    with pytest.raises(AI2ThorUnavailableError, match="ai2thor"):
        AI2ThorExecutor().run(first_task("pick_and_place_simple"), ["done"])
