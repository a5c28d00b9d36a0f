"""Benchmark tasks: reference plans in the skill vocabulary and the stored task sets."""

from talkdem.tasks.reference_plan import ReferencePlanError, object_type_of, reference_plan, reference_skills
from talkdem.tasks.store import (
    Task,
    TaskSet,
    UnknownTaskError,
    get_task,
    load_tasks,
    make_task,
    task_file,
    write_tasks,
)

__all__ = [
    "ReferencePlanError",
    "Task",
    "TaskSet",
    "UnknownTaskError",
    "get_task",
    "load_tasks",
    "make_task",
    "object_type_of",
    "reference_plan",
    "reference_skills",
    "task_file",
    "write_tasks",
]
