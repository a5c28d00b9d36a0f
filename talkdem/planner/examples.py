"""The six task-type examples every SayCan prompt starts with (built by `builders/planner_examples.py`)."""

from __future__ import annotations

import json
from functools import cache
from pathlib import Path

from talkdem.paths import data_dir
from talkdem.planner.prompt import Demonstration

__all__ = ["examples_file", "task_type_examples"]


def examples_file(folder: Path | None = None) -> Path:
    return data_dir(folder) / "prompts" / "saycan_examples.jsonl"


@cache
def task_type_examples(folder: Path | None = None) -> tuple[Demonstration, ...]:
    path = examples_file(folder)
    if not path.is_file():
        raise FileNotFoundError(f"{path}: no planner examples (build them with builders/planner_examples.py)")
    rows = [json.loads(line) for line in path.read_text().splitlines() if line.strip()]
    return tuple(Demonstration(row["instruction"], tuple(row["reference_plan"])) for row in rows)
