"""A dataset folder of a few made-up tasks, written in the shipped layout (card front matter, Parquet files with
the schema's features), so that readers of a dataset folder can be tested on rows whose answers are known."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pyarrow as pa
import pyarrow.parquet as pq

from builders.card import configs_yaml
from talkdem.schema import CLEAN, LEVELS, MEMORY_BANK, PATTERN_CONFIGS, TASKS, data_files, features, split_name

CONDITIONS = [(CLEAN, 0)] + [(p, level) for p in PATTERN_CONFIGS for level in LEVELS]
"""The 16 instructions of a task: its clean control, then each pattern at each level."""


@dataclass(frozen=True)
class TinyTask:
    task_id: str
    task_type: str
    target: str
    task_name: str
    text: Callable[[str, int], str]
    """The instruction of (pattern, level); (clean, 0) is the clean control."""
    seed: str = "Put the thing somewhere."
    failed: frozenset[tuple[str, int]] = frozenset()
    """Conditions whose utterance is kept with a failed check."""


def _row(task: TinyTask, pattern: str, level: int) -> dict[str, Any]:
    failed = (pattern, level) in task.failed
    return {
        "id": f"{task.task_id}:{pattern}:{level}",
        "task_id": task.task_id,
        "task_type": task.task_type,
        "pattern": pattern,
        "level": level,
        "instruction": task.text(pattern, level),
        "clean_instruction": task.text(CLEAN, 0),
        "seed_instruction": task.seed,
        "pddl_params": {
            "object_target": task.target,
            "parent_target": "Shelf",
            "mrecep_target": None,
            "toggle_target": None,
            "object_sliced": False,
        },
        "floor_plan": "FloorPlan1",
        "scene_objects": [task.target, "Shelf"],
        "verification": {"passed": not failed, "failed_checks": ["target_named"] if failed else [], "attempts": 1},
        "generator": "tiny",
        "prompt_version": "tiny-v1",
        "seed": 0,
    }


def _write(rows: list[dict[str, Any]], kind: Any, path: Path) -> None:
    schema = features(kind)
    table = pa.Table.from_pylist([schema.encode_example(r) for r in rows], schema=schema.arrow_schema)
    path.parent.mkdir(parents=True, exist_ok=True)
    pq.write_table(table, path)


def write_tiny_dataset(folder: Path, benchmark: list[TinyTask], memory: list[TinyTask]) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "README.md").write_text(f"---\n{configs_yaml()}\n---\n\n# tiny\n", encoding="utf-8")
    rows = [_row(t, p, lv) for t in benchmark for p, lv in CONDITIONS]
    ((clean_file,),) = data_files(CLEAN).values()
    _write([r for r in rows if r["pattern"] == CLEAN], "instruction", folder / clean_file)
    for pattern in PATTERN_CONFIGS:
        for level in LEVELS:
            (path,) = data_files(pattern)[split_name(level)]
            _write([r for r in rows if (r["pattern"], r["level"]) == (pattern, level)], "instruction", folder / path)
    bank = [
        {**_row(t, p, lv), "interpretation": "Put it there.", "reference_plan": ["find a shelf", "done"]}
        for t in memory
        for p, lv in CONDITIONS
    ]
    ((bank_file,),) = data_files(MEMORY_BANK).values()
    _write(bank, "memory_bank", folder / bank_file)
    for split, tasks in (("benchmark", benchmark), ("memory", memory)):
        (path,) = data_files(TASKS)[split]
        task_rows = [
            {
                "task_id": t.task_id,
                "task_set": split,
                "task_type": t.task_type,
                "task_name": t.task_name,
                "floor_plan": "FloorPlan1",
                "seed_instruction": t.seed,
                "interpretation": "Put it there.",
                "pddl_params": _row(t, CLEAN, 0)["pddl_params"],
                "scene_objects": [t.target],
                "reference_plan": ["done"],
            }
            for t in tasks
        ]
        _write(task_rows, "task", folder / path)
    return folder
