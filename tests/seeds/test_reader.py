"""The ALFRED reader on the real REI-Bench seed pool, and its errors on broken files."""

from __future__ import annotations

import json
import shutil
from collections import Counter
from pathlib import Path

import pytest

from talkdem.paths import ALFRED_DIR_ENV, alfred_dir
from talkdem.seeds import SeedFormatError, SeedTask, iter_seed_files, load_scene_objects, read_seed_file

HEAT_FILE = "pick_heat_then_place_in_recep-AppleSliced-None-Fridge-11/trial_T20190909_060541_202507/pp/ann_1.json"


def test_pool_has_1000_seeds_over_803_trials(seed_pool: list[SeedTask]) -> None:
    assert len(seed_pool) == 1000
    assert len({s.task_id for s in seed_pool}) == 803


def test_task_type_counts_match_the_data_readme(seed_pool: list[SeedTask]) -> None:
    entries = Counter(s.task_type for s in seed_pool)
    trials = Counter(t for t, _ in {(s.task_type, s.task_id) for s in seed_pool})
    assert entries == {
        "look_at_obj_in_light": 150,
        "pick_and_place_simple": 195,
        "pick_and_place_with_movable_recep": 155,
        "pick_clean_then_place_in_recep": 170,
        "pick_cool_then_place_in_recep": 170,
        "pick_heat_then_place_in_recep": 160,
    }
    assert trials["pick_cool_then_place_in_recep"] == 106
    assert trials["look_at_obj_in_light"] == 139


def test_one_record_carries_every_field() -> None:
    seed = read_seed_file(alfred_dir() / HEAT_FILE)
    assert seed.task_id == "trial_T20190909_060541_202507"
    assert seed.task_type == "pick_heat_then_place_in_recep"
    assert seed.repeat_idx == 1
    assert seed.instruction == "Putting a hot apple slice in the fridge"
    assert seed.high_descs[0] == "Turn right and go to the white table"
    assert seed.pddl_params.object_target == "Apple" and seed.pddl_params.parent_target == "Fridge"
    assert seed.pddl_params.object_sliced is True
    assert seed.floor_plan == "FloorPlan11" and seed.scene.scene_num == 11
    assert seed.scene.agent.rotation == 180 and seed.scene.agent.horizon == 30
    assert len(seed.scene.object_poses) == 42
    assert seed.scene.object_poses[0].object_type == "Pan"
    assert "Microwave" in seed.scene.scene_objects and "Fridge" in seed.scene.scene_objects
    assert any(r.object_type == "Fridge" for r in seed.scene.openable_receptacles)
    assert [p.receptacle_type for p in seed.pickup_sources] == ["DiningTable", "Fridge"]
    assert seed.interactions[0].action == "PickupObject"
    assert seed.interactions[0].object_id == "ButterKnife|-02.34|+00.95|+00.26"
    puts = [i for i in seed.interactions if i.action == "PutObject"]
    assert puts[0].receptacle_id == "Fridge|-02.14|+00.00|-01.69"


def test_files_are_read_in_sorted_order() -> None:
    paths = list(iter_seed_files())
    assert paths == sorted(paths)


def _copy_seed(tmp_path: Path) -> Path:
    target = tmp_path / "json_2.1.0" / HEAT_FILE
    target.parent.mkdir(parents=True)
    shutil.copy(alfred_dir() / HEAT_FILE, target)
    return target


@pytest.mark.parametrize(
    ("field_path", "expected_field"),
    [
        (("scene", "floor_plan"), "scene.floor_plan"),
        (("pddl_params", "object_target"), "pddl_params.object_target"),
        (("task_id",), "task_id"),
        (("turk_annotations",), "turk_annotations"),
    ],
)
def test_missing_field_names_file_and_field(tmp_path: Path, field_path: tuple[str, ...], expected_field: str) -> None:
    path = _copy_seed(tmp_path)
    raw = json.loads(path.read_text())
    holder = raw
    for key in field_path[:-1]:
        holder = holder[key]
    del holder[field_path[-1]]
    path.write_text(json.dumps(raw))
    with pytest.raises(SeedFormatError) as caught:
        read_seed_file(path)
    assert caught.value.field == expected_field
    assert str(path) in str(caught.value) and "missing" in str(caught.value)


def test_wrong_type_is_reported(tmp_path: Path) -> None:
    path = _copy_seed(tmp_path)
    raw = json.loads(path.read_text())
    raw["pddl_params"]["object_sliced"] = "yes"
    path.write_text(json.dumps(raw))
    with pytest.raises(SeedFormatError, match=r"pddl_params.object_sliced.*expected bool, got str"):
        read_seed_file(path)


def test_malformed_json_names_the_line(tmp_path: Path) -> None:
    path = _copy_seed(tmp_path)
    path.write_text('{"task_id": "x",\n  "task_type": }')
    with pytest.raises(SeedFormatError, match=r"not valid JSON \(line 2"):
        read_seed_file(path)


def test_missing_file_and_missing_folder(tmp_path: Path) -> None:
    with pytest.raises(SeedFormatError, match="file not found"):
        read_seed_file(tmp_path / "nope.json")
    with pytest.raises(SeedFormatError, match="TALKDEM_ALFRED_DIR"):
        list(iter_seed_files(tmp_path / "absent"))


def test_missing_floor_plan_file_is_named(tmp_path: Path) -> None:
    with pytest.raises(SeedFormatError, match=r"FloorPlan999-objects\.json"):
        load_scene_objects("FloorPlan999", tmp_path)


def test_alfred_dir_follows_the_environment(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    monkeypatch.setenv(ALFRED_DIR_ENV, str(tmp_path))
    assert alfred_dir() == tmp_path
    assert alfred_dir("/elsewhere") == Path("/elsewhere")
