"""The benchmark's instructions and CARE's memory bank, read from the dataset folder's Parquet files.

The dataset folder's README.md declares its configs in YAML (the `datasets` loading contract); this
module reads the same declaration with pyarrow alone, so the planner and the metric never import
`datasets`.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass
from functools import cache
from pathlib import Path
from typing import Any

from talkdem.paths import data_dir
from talkdem.schema import CLEAN, PATTERN_CONFIGS, Condition

__all__ = [
    "Instruction",
    "MemoryItem",
    "dataset_configs",
    "dataset_hash",
    "load_instructions",
    "load_memory_bank",
]


@dataclass(frozen=True)
class Instruction:
    """One benchmark instruction: the clean control or a pattern variant of a task."""

    id: str
    task_id: str
    task_type: str
    condition: Condition
    text: str
    clean_text: str


@dataclass(frozen=True)
class MemoryItem:
    """A resolved held-out task: instruction, gold one-sentence interpretation, reference plan."""

    id: str
    task_id: str
    task_type: str
    condition: Condition
    instruction: str
    interpretation: str
    reference_plan: tuple[str, ...]


def _front_matter(readme: Path) -> dict[str, Any]:
    import yaml

    text = readme.read_text()
    if not text.startswith("---"):
        raise ValueError(f"{readme}: no YAML front matter (the dataset card declares the configs)")
    _, block, _ = text.split("---", 2)
    loaded: dict[str, Any] = yaml.safe_load(block)
    return loaded


@cache
def dataset_configs(folder: Path | None = None) -> dict[str, dict[str, tuple[Path, ...]]]:
    """config -> split -> Parquet files, from the dataset folder's README.md."""
    root = data_dir(folder)
    readme = root / "README.md"
    if not readme.is_file():
        raise FileNotFoundError(f"{readme}: the dataset is not built (run `talkdem build`)")
    configs: dict[str, dict[str, tuple[Path, ...]]] = {}
    for config in _front_matter(readme).get("configs", []):
        splits: dict[str, tuple[Path, ...]] = {}
        for entry in config["data_files"]:
            paths = entry["path"] if isinstance(entry["path"], list) else [entry["path"]]
            splits[entry["split"]] = tuple(root / p for p in paths)
        configs[config["config_name"]] = splits
    return configs


def _class_labels(table: Any) -> dict[str, list[str]]:
    """Column -> names of the columns `datasets` stores as class labels (integers), from the schema's
    `huggingface` metadata: read here so that the planner and the metric never import `datasets`."""
    import json

    metadata = (table.schema.metadata or {}).get(b"huggingface")
    features = json.loads(metadata).get("info", {}).get("features", {}) if metadata else {}
    return {name: list(f["names"]) for name, f in features.items() if f.get("_type") == "ClassLabel"}


def _rows(config: str, folder: Path | None) -> list[dict[str, Any]]:
    import pyarrow.parquet as pq

    configs = dataset_configs(folder)
    if config not in configs:
        raise ValueError(f"the dataset has no config '{config}' (has: {', '.join(configs)})")
    rows: list[dict[str, Any]] = []
    for split in sorted(configs[config]):
        for path in configs[config][split]:
            table = pq.read_table(path)
            labels = _class_labels(table)
            for row in table.to_pylist():
                rows.append({k: labels[k][v] if k in labels and isinstance(v, int) else v for k, v in row.items()})
    return rows


def _condition(pattern: str, row: dict[str, Any]) -> Condition:
    return Condition(CLEAN, 0) if pattern == CLEAN else Condition(pattern, int(row["level"]))


@cache
def load_instructions(folder: Path | None = None) -> tuple[Instruction, ...]:
    """All 4,800 instructions: clean controls first, then each pattern by level (ids are unique)."""
    instructions = []
    for config in (CLEAN, *PATTERN_CONFIGS):
        for row in _rows(config, folder):
            condition = _condition(config, row)
            instructions.append(
                Instruction(
                    id=row["id"],
                    task_id=row["task_id"],
                    task_type=row["task_type"],
                    condition=condition,
                    text=row["instruction"],
                    clean_text=row["clean_instruction"],
                )
            )
    return tuple(sorted(instructions, key=lambda i: (i.condition, i.task_id)))


@cache
def load_memory_bank(folder: Path | None = None) -> tuple[MemoryItem, ...]:
    """CARE's 1,600 memory items, in a stable order."""
    items = []
    for row in _rows("memory_bank", folder):
        condition = _condition(row["pattern"], row)
        items.append(
            MemoryItem(
                id=row["id"],
                task_id=row["task_id"],
                task_type=row["task_type"],
                condition=condition,
                instruction=row["instruction"],
                interpretation=row["interpretation"],
                reference_plan=tuple(row["reference_plan"]),
            )
        )
    return tuple(sorted(items, key=lambda m: m.id))


@cache
def dataset_hash(folder: Path | None = None) -> str:
    """sha256 over the dataset's declared Parquet files (names and bytes): recorded in every result file."""
    digest = hashlib.sha256()
    root = data_dir(folder)
    # Each file once: the `all` config declares the instruction files a second time.
    files = {path for splits in dataset_configs(folder).values() for paths in splits.values() for path in paths}
    for path in sorted(files):
        digest.update(path.relative_to(root).as_posix().encode() + b"\0" + path.read_bytes())
    return digest.hexdigest()
