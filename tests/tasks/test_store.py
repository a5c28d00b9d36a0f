"""The stored task sets under data/tasks/: shape, disjointness, round trip against the seeds."""

from __future__ import annotations

from collections import Counter
from pathlib import Path

import pytest

from talkdem.paths import alfred_dir
from talkdem.seeds import SeedTask, read_seed_file
from talkdem.tasks import TaskSet, UnknownTaskError, get_task, load_tasks, reference_plan, write_tasks


def test_benchmark_has_50_tasks_per_type_and_memory_100() -> None:
    benchmark = load_tasks(TaskSet.BENCHMARK)
    memory = load_tasks(TaskSet.MEMORY)
    assert len(benchmark) == 300 and len(memory) == 100
    assert set(Counter(t.task_type for t in benchmark).values()) == {50}
    assert sorted(Counter(t.task_type for t in memory).values()) == [16, 16, 17, 17, 17, 17]
    assert not {t.task_id for t in benchmark} & {t.task_id for t in memory}
    assert len({t.task_id for t in benchmark}) == 300


def test_stored_tasks_equal_a_fresh_read_of_their_seed_files() -> None:
    for task in load_tasks(TaskSet.MEMORY)[:25]:
        seed = read_seed_file(alfred_dir() / task.source_file)
        assert tuple(reference_plan(seed)) == task.reference_plan
        stored_seed_fields = {name: getattr(task, name) for name in SeedTask.__dataclass_fields__}
        assert SeedTask(**stored_seed_fields) == seed


def test_get_task_and_unknown_id() -> None:
    task = load_tasks(TaskSet.BENCHMARK)[7]
    assert get_task(task.task_id) == task
    with pytest.raises(UnknownTaskError, match="unknown task id 'trial_nope'"):
        get_task("trial_nope")


def test_corrupt_task_file_names_the_line(tmp_path: Path) -> None:
    tasks = list(load_tasks(TaskSet.MEMORY)[:3])
    path = tmp_path / "tasks" / "memory.jsonl"
    write_tasks(tasks, path)
    lines = path.read_text().splitlines()
    lines[1] = lines[1].replace('"task_type"', '"task_kind"')
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(ValueError, match=r"memory.jsonl, line 2: task_type: missing"):
        load_tasks(TaskSet.MEMORY, tmp_path)
