"""Real tasks from data/tasks, chosen by type, for the simulator tests."""

from __future__ import annotations

import dataclasses

from talkdem.tasks import Task, TaskSet, load_tasks


def all_tasks() -> list[Task]:
    return [task for task_set in TaskSet for task in load_tasks(task_set)]


def first_task(task_type: str, *, plan_has: str = "", sliced: bool | None = None) -> Task:
    for task in load_tasks(TaskSet.BENCHMARK):
        if task.task_type != task_type or (sliced is not None and task.pddl_params.object_sliced != sliced):
            continue
        if plan_has and not any(plan_has in step for step in task.reference_plan):
            continue
        return task
    raise LookupError(task_type)


def with_plan(task: Task, plan: list[str]) -> Task:
    return dataclasses.replace(task, reference_plan=tuple(plan))
