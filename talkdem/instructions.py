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
    "config_rows",
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
    from talkdem.yaml_input import YamlInputError, load_yaml

    text = readme.read_text(encoding="utf-8")
    parts = text.split("---", 2)
    if not text.startswith("---") or len(parts) < 3:
        raise ValueError(f"{readme}: no YAML front matter between '---' lines (the dataset card declares the configs)")
    try:
        # The package's bounded reader (no alias bomb, no duplicate key), as for every YAML file read.
        loaded = load_yaml(parts[1])
    except YamlInputError as exc:
        # The block starts on the file's first line (after its '---'): its line k is the file's line k.
        where = f"{readme}:{exc.line}" if exc.line is not None else str(readme)
        verb = "does not parse" if exc.syntax else "is refused"
        raise ValueError(f"{where}: the card's YAML front matter {verb} ({exc.problem})") from None
    if not isinstance(loaded, dict):
        raise ValueError(f"{readme}: the YAML front matter is not a mapping (it declares `configs:`)")
    return loaded


@cache
def dataset_configs(folder: Path | None = None) -> dict[str, dict[str, tuple[Path, ...]]]:
    """config -> split -> Parquet files, from the dataset folder's README.md."""
    root = data_dir(folder)
    readme = root / "README.md"
    if not readme.is_file():
        raise FileNotFoundError(f"{readme}: the dataset is not built (run `talkdem build`)")
    configs: dict[str, dict[str, tuple[Path, ...]]] = {}
    declared = _front_matter(readme).get("configs", [])
    if not isinstance(declared, list):
        raise ValueError(f"{readme}: `configs` in the front matter must be a list")
    for n, config in enumerate(declared, start=1):
        try:
            splits: dict[str, tuple[Path, ...]] = {}
            for entry in config["data_files"]:
                paths = entry["path"] if isinstance(entry["path"], list) else [entry["path"]]
                splits[str(entry["split"])] = tuple(root / str(p) for p in paths)
            configs[str(config["config_name"])] = splits
        except (KeyError, TypeError) as exc:
            raise ValueError(
                f"{readme}: config {n} of the front matter needs `config_name` and `data_files` entries with "
                f"`split` and `path` (missing or malformed: {exc})"
            ) from None
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
            try:
                table = pq.read_table(path)
                labels = _class_labels(table)
                found = table.to_pylist()
            except OSError as exc:
                if exc.strerror:  # a missing or unreadable file: the CLI names it from the OSError
                    raise
                raise ValueError(f"{path}: cannot read this Parquet file ({exc}); rebuild or restore it") from None
            except Exception as exc:  # pyarrow's errors (a corrupted page: "ZSTD decompression failed") name no file
                raise ValueError(f"{path}: cannot read this Parquet file ({exc}); rebuild or restore it") from None
            for row in found:
                rows.append({k: labels[k][v] if k in labels and isinstance(v, int) else v for k, v in row.items()})
    return rows


def config_rows(config: str, folder: Path | None = None) -> list[dict[str, Any]]:
    """Every row of one config as plain dicts, class labels as their names (splits in sorted order): for readers
    that need fields the typed records leave out (`seed_instruction`, `pddl_params`, `task_name`)."""
    return _rows(config, folder)


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
