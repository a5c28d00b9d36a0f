"""What a run covered: tasks per condition out of the benchmark's, and a fingerprint of its episode set.

Two runs are comparable only over the same episodes of the same dataset; the fingerprint (`task_set`) makes
that a string comparison.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass
from functools import cache
from typing import Any

from talkdem.metrics import Scores
from talkdem.metrics.rates import condition_key
from talkdem.schema import CONDITIONS

__all__ = ["Coverage", "benchmark_tasks", "coverage_of"]


@cache
def benchmark_tasks() -> int:
    """The number of benchmark tasks in the dataset (300)."""
    from talkdem.instructions import load_instructions

    return len({i.task_id for i in load_instructions()})


@dataclass(frozen=True)
class Coverage:
    """Tasks evaluated under each of the 16 conditions, out of `of_tasks`."""

    tasks_per_condition: dict[str, int]
    """Condition key (`clean`, `intrusion:3`) -> tasks evaluated under it (0 when not run)."""
    tasks: int
    """Distinct tasks with at least one episode."""
    of_tasks: int
    task_set: str
    """sha256 (16 hex digits) of the sorted episodes (task, condition): equal for runs over the same episodes."""
    episodes: int = 0
    """Episodes on disk."""
    planned_episodes: int | None = None
    """Episodes the run was asked for (its header); None for runs that did not record it."""

    @property
    def complete(self) -> bool:
        return self.planned_episodes is None or self.episodes >= self.planned_episodes

    @property
    def conditions(self) -> int:
        return sum(1 for n in self.tasks_per_condition.values() if n)

    @property
    def of_conditions(self) -> int:
        return len(self.tasks_per_condition)

    def describe(self) -> str:
        """`24/300 tasks × 16/16 conditions`, with the range of tasks per condition when it varies."""
        counts = sorted({n for n in self.tasks_per_condition.values() if n})
        per = "" if len(counts) <= 1 else f" ({counts[0]}–{counts[-1]} per condition)"
        partial = "" if self.complete else f", INCOMPLETE: {self.episodes} of {self.planned_episodes} planned episodes"
        return f"{self.tasks}/{self.of_tasks} tasks × {self.conditions}/{self.of_conditions} conditions{per}{partial}"

    @classmethod
    def from_json(cls, data: dict[str, Any]) -> Coverage:
        return cls(
            tasks_per_condition={str(k): int(v) for k, v in data["tasks_per_condition"].items()},
            tasks=int(data["tasks"]),
            of_tasks=int(data["of_tasks"]),
            task_set=str(data["task_set"]),
            episodes=int(data.get("episodes", 0)),
            planned_episodes=None if data.get("planned_episodes") is None else int(data["planned_episodes"]),
        )

    def to_json(self) -> dict[str, Any]:
        return {
            "tasks": self.tasks,
            "of_tasks": self.of_tasks,
            "conditions": self.conditions,
            "of_conditions": self.of_conditions,
            "tasks_per_condition": dict(self.tasks_per_condition),
            "task_set": self.task_set,
            "episodes": self.episodes,
            "planned_episodes": self.planned_episodes,
            "complete": self.complete,
        }


def coverage_of(scores: Scores, planned_episodes: int | None = None) -> Coverage:
    per: dict[str, set[str]] = {condition_key(c): set() for c in CONDITIONS}
    for episode in scores.episodes:
        per[condition_key(episode.condition)].add(episode.task_id)
    # Task and condition, not the id as written: `<task>:clean` and `<task>:clean:0` are the same episode.
    episodes = sorted({f"{e.task_id}:{condition_key(e.condition)}" for e in scores.episodes})
    digest = hashlib.sha256("\n".join(episodes).encode()).hexdigest()
    return Coverage(
        tasks_per_condition={k: len(v) for k, v in per.items()},
        tasks=len({e.task_id for e in scores.episodes}),
        of_tasks=benchmark_tasks(),
        task_set=digest[:16],
        episodes=len(scores.episodes),
        planned_episodes=planned_episodes,
    )
