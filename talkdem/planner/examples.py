"""The six task-type examples every SayCan prompt starts with (built by `builders/planner_examples.py`)."""

from __future__ import annotations

import json
from functools import cache
from pathlib import Path

from talkdem.paths import data_dir
from talkdem.planner.prompt import Demonstration
from talkdem.plans import as_plan

__all__ = ["examples_file", "task_type_examples"]


def examples_file(folder: Path | None = None) -> Path:
    return data_dir(folder) / "prompts" / "saycan_examples.jsonl"


@cache
def task_type_examples(folder: Path | None = None) -> tuple[Demonstration, ...]:
    path = examples_file(folder)
    if not path.is_file():
        raise FileNotFoundError(f"{path}: no planner examples (build them with builders/planner_examples.py)")
    examples = []
    for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), start=1):
        if not line.strip():
            continue
        try:
            row = json.loads(line)
        except json.JSONDecodeError as exc:
            raise ValueError(f"{path}:{number}: not a JSON line ({exc.msg}, column {exc.colno})") from None
        instruction = row.get("instruction") if isinstance(row, dict) else None
        plan = as_plan(row.get("reference_plan")) if isinstance(row, dict) else None
        if not isinstance(instruction, str) or plan is None:
            raise ValueError(
                f"{path}:{number}: an example needs 'instruction' (a string) and 'reference_plan' (a list of skill "
                "strings)"
            )
        examples.append(Demonstration(instruction, plan))
    return tuple(examples)
