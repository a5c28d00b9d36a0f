"""Which episodes a run covers: conditions x tasks, sampled so that every condition sees the same tasks."""

from __future__ import annotations

from collections.abc import Sequence

from talkdem.instructions import Instruction, load_instructions
from talkdem.schema import Condition

__all__ = ["select_episodes", "stratified_task_ids"]


def stratified_task_ids(instructions: Sequence[Instruction], limit: int | None) -> list[str]:
    """`limit` tasks spread over the task types (round robin over types sorted by name, tasks by id);
    all tasks when `limit` is None. The same tasks serve every condition, so retention stays paired."""
    by_type: dict[str, list[str]] = {}
    for instruction in instructions:
        ids = by_type.setdefault(instruction.task_type, [])
        if instruction.task_id not in ids:
            ids.append(instruction.task_id)
    queues = [sorted(ids) for _, ids in sorted(by_type.items())]
    total = sum(len(q) for q in queues)
    wanted = total if limit is None else min(limit, total)
    chosen: list[str] = []
    depth = 0
    while len(chosen) < wanted:
        for queue in queues:
            if depth < len(queue) and len(chosen) < wanted:
                chosen.append(queue[depth])
        depth += 1
    return chosen


def select_episodes(conditions: Sequence[Condition], limit: int | None) -> list[Instruction]:
    """The instructions of a run, ordered by task then condition (the clean control of a task first)."""
    instructions = load_instructions()
    tasks = stratified_task_ids(instructions, limit)
    wanted = set(conditions)
    rank = {task_id: i for i, task_id in enumerate(tasks)}
    chosen = [i for i in instructions if i.task_id in rank and i.condition in wanted]
    return sorted(chosen, key=lambda i: (rank[i.task_id], i.condition))
