"""The shipped folder loads offline with `datasets` for every config and split, and through `talk_dem.load`."""

from __future__ import annotations

from pathlib import Path

import datasets
import pytest

import talk_dem
from talkdem.paths import repo_root

DATA = repo_root() / "data"
SPLITS = {
    **{pattern: [talk_dem.split_name(level) for level in talk_dem.LEVELS] for pattern in talk_dem.PATTERNS},
    "clean": ["test"],
    "all": ["test"],
    "memory_bank": ["train"],
    "tasks": ["benchmark", "memory"],
}
ROWS = {"clean": 300, "all": 4800, "memory_bank": 1600, "benchmark": 300, "memory": 100}
CASES = [(config, split) for config, splits in SPLITS.items() for split in splits]


@pytest.fixture(autouse=True)
def offline(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("HF_HUB_OFFLINE", "1")
    monkeypatch.setenv("HF_DATASETS_OFFLINE", "1")


def test_configs_cover_the_declared_ones() -> None:
    assert set(SPLITS) == set(talk_dem.CONFIGS)
    assert datasets.get_dataset_config_names(str(DATA)) is not None


@pytest.mark.parametrize(("config", "split"), CASES, ids=[f"{c}-{s}" for c, s in CASES])
def test_every_config_and_split_loads(config: str, split: str, tmp_path: Path) -> None:
    ds = datasets.load_dataset(str(DATA), config, split=split, cache_dir=str(tmp_path))
    assert isinstance(ds, datasets.Dataset)
    assert ds.num_rows == ROWS.get(split, ROWS.get(config, 300))
    expected = {"memory_bank": talk_dem.MEMORY_BANK_FEATURES, "tasks": talk_dem.TASK_FEATURES}.get(
        config, talk_dem.INSTRUCTION_FEATURES
    )
    assert ds.features == expected
    if config in talk_dem.PATTERNS:
        level = int(split.removeprefix("level_"))
        assert {ds.features["pattern"].int2str(p) for p in ds["pattern"]} == {config}
        assert set(ds["level"]) == {level}
        assert len(set(ds["task_id"])) == 300


def test_rows_carry_ids_clean_seed_params_verification_and_provenance(tmp_path: Path) -> None:
    ds = datasets.load_dataset(str(DATA), "topic_drift", split="level_3", cache_dir=str(tmp_path))
    row = ds[0]
    assert row["id"] == f"{row['task_id']}:topic_drift:3"
    assert row["instruction"] != row["clean_instruction"]
    assert row["seed_instruction"]
    assert set(row["pddl_params"]) == {
        "object_target",
        "parent_target",
        "mrecep_target",
        "toggle_target",
        "object_sliced",
    }
    assert set(row["verification"]) == {"passed", "failed_checks", "attempts"}
    assert row["generator"] == "rules" and row["prompt_version"] and isinstance(row["seed"], int)


def test_clean_and_variants_share_the_clean_control(tmp_path: Path) -> None:
    clean = datasets.load_dataset(str(DATA), "clean", split="test", cache_dir=str(tmp_path))
    variants = datasets.load_dataset(str(DATA), "intrusion", split="level_1", cache_dir=str(tmp_path))
    by_task = dict(zip(clean["task_id"], clean["instruction"], strict=True))
    assert all(by_task[t] == c for t, c in zip(variants["task_id"], variants["clean_instruction"], strict=True))


def test_memory_bank_is_disjoint_and_complete(tmp_path: Path) -> None:
    bank = datasets.load_dataset(str(DATA), "memory_bank", split="train", cache_dir=str(tmp_path))
    tasks = datasets.load_dataset(str(DATA), "tasks", cache_dir=str(tmp_path))
    assert set(bank["task_id"]) == set(tasks["memory"]["task_id"])
    assert not set(bank["task_id"]) & set(tasks["benchmark"]["task_id"])
    assert all(bank["interpretation"]) and all(bank["reference_plan"])
    names = bank.features["pattern"].int2str
    assert sorted({(names(p), lvl) for p, lvl in zip(bank["pattern"], bank["level"], strict=True)}) == sorted(
        [("clean", 0)] + [(p, lvl) for p in talk_dem.PATTERNS for lvl in talk_dem.LEVELS]
    )


def test_combined_splits_load(tmp_path: Path) -> None:
    ds = datasets.load_dataset(str(DATA), "empty_speech", split="level_1+level_2", cache_dir=str(tmp_path))
    assert ds.num_rows == 600


def test_talk_dem_load(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    ds = talk_dem.load("object_substitution", 2, cache_dir=str(tmp_path))
    assert ds.num_rows == 300 and set(ds["level"]) == {2}
    assert talk_dem.load("memory_bank", cache_dir=str(tmp_path)).num_rows == 1600
    with pytest.raises(ValueError, match="needs a level"):
        talk_dem.load("intrusion")
    with pytest.raises(ValueError, match="unknown config"):
        talk_dem.load("whispering", 1)


def test_loader_module_does_not_clash_with_the_dataset_folder() -> None:
    # datasets refuses a folder `foo/` holding `foo.py`: the declaration module stays outside data/
    assert not list(DATA.glob("*.py"))
    assert (repo_root() / "talk_dem.py").is_file()


def test_talk_dem_load_takes_a_split_and_the_clean_level_zero(tmp_path: Path) -> None:
    assert talk_dem.load("tasks", split="memory", cache_dir=str(tmp_path)).num_rows == 100
    assert talk_dem.load("tasks", cache_dir=str(tmp_path)).num_rows == 300
    assert talk_dem.load("clean", 0, cache_dir=str(tmp_path)).num_rows == 300
    with pytest.raises(ValueError, match="has no levels"):
        talk_dem.load("tasks", 0)
    with pytest.raises(ValueError, match="either a level or a split"):
        talk_dem.load("intrusion", 2, split="level_3")
    with pytest.raises(ValueError, match="neither a dataset folder nor a Hub repository id"):
        talk_dem.load("clean", path="no-such-folder")


def _copy_with_edit(folder: Path, text: str | None, config: str = "intrusion", split: str = "level_2") -> Path:
    """A copy of the dataset named `data` (as every checkout's is) under `folder`, with the first row of
    `config/split` reading `text` (None: unedited)."""
    import shutil

    copy = folder / "data"
    shutil.copytree(DATA, copy, ignore=shutil.ignore_patterns("parity", "tasks"))
    if text is not None:
        _edit_first_row(copy, text, config, split)
    return copy


def _edit_first_row(copy: Path, text: str, config: str = "intrusion", split: str = "level_2") -> None:
    import pyarrow as pa
    import pyarrow.parquet as pq

    path = copy / config / f"{split}.parquet"
    table = pq.read_table(path)
    rows = table.to_pylist()
    rows[0]["instruction"] = text
    pq.write_table(pa.Table.from_pylist(rows, schema=table.schema), path)


def test_the_loader_reads_what_is_on_disk(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    # One Hugging Face cache for everything, as on a user's machine: a second folder named `data`, or an
    # edit in place, must not be answered with the rows cached for the first.
    monkeypatch.setattr(datasets.config, "HF_DATASETS_CACHE", tmp_path / "hf")
    first = _copy_with_edit(tmp_path / "a", None)
    second = _copy_with_edit(tmp_path / "b", "an edited second copy")
    monkeypatch.setenv("TALKDEM_DATA_DIR", str(first))
    original = talk_dem.load("intrusion", 2)[0]["instruction"]
    assert original != "an edited second copy"
    monkeypatch.setenv("TALKDEM_DATA_DIR", str(second))
    assert talk_dem.load("intrusion", 2)[0]["instruction"] == "an edited second copy"
    assert talk_dem.load("intrusion", 2, path=str(first))[0]["instruction"] == original
    _edit_first_row(first, "edited in place")
    monkeypatch.setenv("TALKDEM_DATA_DIR", str(first))
    assert talk_dem.load("intrusion", 2)[0]["instruction"] == "edited in place"


def test_the_readme_load_dataset_example_reads_the_folder_it_names(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    """The README's `datasets.load_dataset` line for the local dataset folder (`"data"` in a checkout's root,
    or the folder the package names), run as written in two checkouts whose `data/` differ: each must load
    its own rows, not the first one's from the shared cache."""
    import re

    readme = (repo_root() / "README.md").read_text(encoding="utf-8")
    pattern = r'^(\w+) = datasets\.load_dataset\(("data"|talk_dem\.data_dir\(\)), "(\w+)", split="(\w+)".*$'
    found = re.search(pattern, readme, flags=re.MULTILINE)
    assert found, "the README shows loading the local dataset folder with datasets.load_dataset"
    example, name, config, split = found.group(0), found.group(1), found.group(3), found.group(4)
    monkeypatch.setattr(datasets.config, "HF_DATASETS_CACHE", tmp_path / "hf")
    for checkout, text in (("a", "the first checkout"), ("b", "the second checkout")):
        copy = _copy_with_edit(tmp_path / checkout, text, config, split)
        monkeypatch.chdir(tmp_path / checkout)
        monkeypatch.setenv("TALKDEM_DATA_DIR", str(copy))
        scope: dict[str, object] = {"datasets": datasets, "talk_dem": talk_dem}
        exec(example, scope)
        loaded = scope[name]
        assert isinstance(loaded, datasets.Dataset) and loaded[0]["instruction"] == text
