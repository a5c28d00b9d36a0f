"""The memory bank shares no ALFRED task and no seed text with the benchmark (`MEMORY_RULE`), and the rule
leaves the benchmark as it was."""

from __future__ import annotations

import hashlib
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pytest
from numpy.typing import NDArray

from builders.selection import (
    greedy_max_min,
    normalise_seed_text,
    one_seed_per_trial,
    select_tasks,
    shares_benchmark_task,
    write_selection,
)
from talkdem.paths import repo_root
from talkdem.seeds import SeedTask
from talkdem.tasks import TaskSet, load_tasks, task_file


def _bag_of_letters(texts: Sequence[str]) -> NDArray[np.float64]:
    rows = np.array([[t.lower().count(ch) + 0.1 for ch in "abcdefghijklmnopqrstuvwxyz"] for t in texts])
    return np.asarray(rows / np.linalg.norm(rows, axis=1, keepdims=True), dtype=np.float64)


def test_normalised_seed_text_ignores_case_punctuation_and_spacing() -> None:
    assert normalise_seed_text("Put the  apple, in the FRIDGE.") == normalise_seed_text("put the apple in the fridge")
    assert normalise_seed_text("Put the apple in the fridge") != normalise_seed_text("Put the apples in the fridge")


def test_the_committed_memory_tasks_share_no_alfred_task_or_seed_text_with_the_benchmark() -> None:
    benchmark, memory = load_tasks(TaskSet.BENCHMARK), load_tasks(TaskSet.MEMORY)
    assert len(benchmark) == 300 and len(memory) == 100
    assert not {t.task_name for t in benchmark} & {t.task_name for t in memory}
    seeds = {normalise_seed_text(t.instruction) for t in benchmark}
    assert not [t.task_id for t in memory if normalise_seed_text(t.instruction) in seeds]
    assert not [t.task_id for t in memory if shares_benchmark_task(t, benchmark)]
    assert not {t.task_id for t in benchmark} & {t.task_id for t in memory}


def test_the_rule_is_applied_and_leaves_the_benchmark_alone(seed_pool: list[SeedTask]) -> None:
    selection = select_tasks(seed_pool, encode=_bag_of_letters)
    benchmark = selection.benchmark
    # The benchmark is plain greedy max-min within each type, computed here without the selection's code path.
    candidates = one_seed_per_trial(seed_pool)
    expected = []
    for task_type in sorted({c.task_type for c in candidates}):
        members = [c for c in candidates if c.task_type == task_type]
        vectors = _bag_of_letters([c.instruction for c in members])
        expected += [members[i].task_id for i in greedy_max_min(vectors @ vectors.T, 50)]
    assert [s.task_id for s in benchmark] == expected
    assert not [m.task_id for m in selection.memory if shares_benchmark_task(m, benchmark)]
    # Every trial left out shares something with the benchmark, and none of them is a benchmark trial.
    assert selection.shared_with_benchmark
    chosen = {b.task_id for b in benchmark}
    by_id = {c.task_id: c for c in candidates}
    for task_id in selection.shared_with_benchmark:
        assert task_id not in chosen and shares_benchmark_task(by_id[task_id], benchmark)


@pytest.mark.slow
def test_minilm_selection_rewrites_the_task_files_byte_for_byte(seed_pool: list[SeedTask], tmp_path: Path) -> None:
    selection = select_tasks(seed_pool)
    write_selection(selection, tmp_path)
    for task_set in TaskSet:
        fresh = task_file(task_set, tmp_path).read_bytes()
        shipped = task_file(task_set).read_bytes()
        assert hashlib.sha256(fresh).hexdigest() == hashlib.sha256(shipped).hexdigest(), task_set
    for name in ("diversity.json", "diversity.md"):
        assert (tmp_path / "selection" / name).read_bytes() == (repo_root() / "data" / "selection" / name).read_bytes()
