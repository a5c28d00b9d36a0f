"""The benchmark's task records: seeds with their reference plans, stored under `data/tasks/`.

The builders (`builders/selection`) write `data/tasks/benchmark.jsonl` (300 tasks) and
`data/tasks/memory.jsonl` (100 memory-bank tasks) from the ALFRED seed pool; everything downstream (the
simulator, the planner, the metric) reads these files and never needs the ALFRED download.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, replace
from enum import StrEnum
from functools import cache
from pathlib import Path

from talkdem.paths import data_dir
from talkdem.seeds.records import SeedTask
from talkdem.serialization import from_jsonable, to_jsonable
from talkdem.tasks.expert_route import route_like_the_expert
from talkdem.tasks.reference_plan import reference_plan, reference_steps

__all__ = [
    "Task",
    "TaskSet",
    "UnknownTaskError",
    "get_task",
    "load_tasks",
    "make_task",
    "task_file",
    "write_tasks",
]


class TaskSet(StrEnum):
    """The two disjoint task sets of TALK-Dem."""

    BENCHMARK = "benchmark"
    """300 tasks (50 per ALFRED task type) behind the 4,800 instructions."""
    MEMORY = "memory"
    """100 held-out tasks behind CARE's memory bank."""


@dataclass(frozen=True)
class Task(SeedTask):
    """A benchmark task: its seed record plus the reference plan in the skill vocabulary."""

    task_set: str
    reference_plan: tuple[str, ...]
    scene_fixture_ids: tuple[str, ...] = ()
    """Ids of fixed objects (faucets, lamps, burners, ...) of this floor plan that any seed trajectory
    touches: the object poses list only pickupables, and fixtures are the same in every trial of a floor
    plan. Stored per task so that a task's initial state never depends on which other tasks were selected."""


class UnknownTaskError(KeyError):
    """A task id that is in neither task set."""

    def __str__(self) -> str:
        return str(self.args[0])


def make_task(seed: SeedTask, task_set: TaskSet, fixture_ids: tuple[str, ...] = ()) -> Task:
    """The task with its reference plan: the plain conversion, or, if that fails in the simulator because a
    `find` reaches another instance than the expert's, the conversion routed past landmarks (`expert_route`)."""
    fields = {name: getattr(seed, name) for name in SeedTask.__dataclass_fields__}
    task = Task(
        **fields,
        task_set=task_set.value,
        reference_plan=tuple(reference_plan(seed)),
        scene_fixture_ids=tuple(sorted(fixture_ids)),
    )
    if _runs_clean(task, task.reference_plan):
        return task
    routed = tuple(skill.text for skill in route_like_the_expert(task, reference_steps(seed)))
    if routed != task.reference_plan and _runs_clean(task, routed):
        return replace(task, reference_plan=routed)
    return task


def _runs_clean(task: Task, plan: tuple[str, ...]) -> bool:
    """The plan reaches the goal and every step succeeds."""
    from talkdem.sim import run_plan

    trace = run_plan(task, plan)
    return trace.success and all(step.ok for step in trace.steps)


def task_file(task_set: TaskSet | str, folder: Path | None = None) -> Path:
    return data_dir(folder) / "tasks" / f"{TaskSet(task_set).value}.jsonl"


def write_tasks(tasks: list[Task], path: Path) -> None:
    """One JSON object per line, keys in field order, so the file diffs cleanly between builds."""
    path.parent.mkdir(parents=True, exist_ok=True)
    lines = [json.dumps(to_jsonable(task), ensure_ascii=False) for task in tasks]
    path.write_text("\n".join(lines) + "\n")


@cache
def _load(path: Path) -> tuple[Task, ...]:
    if not path.is_file():
        raise FileNotFoundError(
            f"{path}: task file not found (not a TALK-Dem dataset folder: point TALKDEM_DATA_DIR at one, "
            "or reinstall the package, whose wheel carries the dataset)"
        )
    tasks = []
    for line_no, line in enumerate(path.read_text().splitlines(), start=1):
        if not line.strip():
            continue
        try:
            tasks.append(from_jsonable(Task, json.loads(line)))
        except (ValueError, json.JSONDecodeError) as exc:
            raise ValueError(f"{path}, line {line_no}: {exc}") from exc
    return tuple(tasks)


def load_tasks(task_set: TaskSet | str, folder: Path | None = None) -> tuple[Task, ...]:
    """The tasks of one set, in the order the selection produced them (grouped by task type)."""
    return _load(task_file(task_set, folder).resolve())


@cache
def _index(folder: Path | None) -> dict[str, Task]:
    return {task.task_id: task for task_set in TaskSet for task in load_tasks(task_set, folder)}


def get_task(task_id: str, folder: Path | None = None) -> Task:
    """A task of either set by its ALFRED trial id; `UnknownTaskError` names the id if absent."""
    index = _index(folder)
    if task_id not in index:
        raise UnknownTaskError(
            f"unknown task id '{task_id}': not among the {len(index)} benchmark and memory tasks "
            f"(list them with `talkdem tasks --set benchmark`)"
        )
    return index[task_id]
