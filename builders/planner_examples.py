"""The six task-type examples of the SayCan prompt: one seed per ALFRED task type, drawn from trials that
are in neither the benchmark nor the memory bank (so no evaluated task leaks into the prompt).

Rule: per task type, among the left-over trials (lowest `repeat_idx` annotation each), the one with the
lowest trial id. Written to `data/prompts/saycan_examples.jsonl`.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path

from builders.selection import one_seed_per_trial
from talkdem.planner.examples import examples_file
from talkdem.seeds import SeedTask
from talkdem.tasks import TaskSet, load_tasks, reference_plan

__all__ = ["select_examples", "write_examples"]


def select_examples(seeds: Sequence[SeedTask]) -> list[SeedTask]:
    used = {task.task_id for task_set in TaskSet for task in load_tasks(task_set)}
    left = [seed for seed in one_seed_per_trial(seeds) if seed.task_id not in used]
    chosen: dict[str, SeedTask] = {}
    for seed in sorted(left, key=lambda s: s.task_id):
        chosen.setdefault(seed.task_type, seed)
    return [chosen[task_type] for task_type in sorted(chosen)]


def write_examples(seeds: Sequence[SeedTask], path: Path | None = None) -> Path:
    path = path or examples_file()
    path.parent.mkdir(parents=True, exist_ok=True)
    rows = [
        {
            "task_id": seed.task_id,
            "task_type": seed.task_type,
            "instruction": seed.instruction,
            "reference_plan": reference_plan(seed),
        }
        for seed in select_examples(seeds)
    ]
    path.write_text("".join(json.dumps(row) + "\n" for row in rows))
    return path
