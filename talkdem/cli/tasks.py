"""`talkdem tasks`: list the benchmark or memory-bank tasks."""

from __future__ import annotations

import argparse
import json
import sys
from dataclasses import asdict
from typing import Any

from talkdem.tasks import Task, TaskSet, load_tasks

__all__ = ["register", "task_summary"]


def register(subparsers: Any) -> None:
    parser = subparsers.add_parser("tasks", help="list the 300 benchmark or 100 memory-bank tasks")
    parser.add_argument("--set", dest="task_set", choices=[s.value for s in TaskSet], default="benchmark")
    parser.add_argument("--format", choices=["jsonl", "table"], default="table")
    parser.add_argument("--full", action="store_true", help="jsonl: every stored field (initial scene included)")
    parser.set_defaults(handler=run)


def task_summary(task: Task) -> dict[str, Any]:
    """The fields a planner or a user needs to see, as one JSON-ready object."""
    return {
        "task_id": task.task_id,
        "task_type": task.task_type,
        "floor_plan": task.floor_plan,
        "instruction": task.instruction,
        "reference_plan": list(task.reference_plan),
        "scene_objects": list(task.scene.scene_objects),
        "pddl_params": asdict(task.pddl_params),
    }


def run(args: argparse.Namespace) -> int:
    if args.full and args.format != "jsonl":
        raise ValueError("--full applies to --format jsonl (the table shows one summary line per task)")
    tasks = load_tasks(args.task_set)
    out = sys.stdout
    if args.format == "jsonl":
        from talkdem.serialization import to_jsonable

        for task in tasks:
            record = to_jsonable(task) if args.full else task_summary(task)
            out.write(json.dumps(record, ensure_ascii=False) + "\n")
        return 0
    out.write(f"{'task_id':32} {'task_type':34} {'floor_plan':12} instruction\n")
    for task in tasks:
        out.write(f"{task.task_id:32} {task.task_type:34} {task.floor_plan:12} {task.instruction}\n")
    out.write(f"{len(tasks)} {args.task_set} tasks\n")
    return 0
