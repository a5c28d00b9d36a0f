"""CARE's retrieval diagnostics on a tiny synthetic dataset whose top-1 items are known by construction, and
the card's fragment that shows them only while they describe the build."""

from __future__ import annotations

import json
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np
import pytest
from numpy.typing import NDArray
from tiny_dataset import TinyTask, write_tiny_dataset

from builders.selection import MEMORY_RULE
from builders.selection.retrieval import (
    ALL_VARIANTS,
    QueryLabels,
    compute_retrieval,
    memory_bank_section,
    retrieval_file,
    top1_agreement,
    write_retrieval,
)
from talkdem.schema import CLEAN, PATTERN_CONFIGS


def _bag_of_words() -> Callable[[Sequence[str]], NDArray[np.float64]]:
    """Word counts over a vocabulary that grows with each new word (collision-free), unit-normalised: equal
    texts have similarity 1, texts without a shared word 0."""
    vocabulary: dict[str, int] = {}

    def encode(texts: Sequence[str]) -> NDArray[np.float64]:
        for text in texts:
            for word in text.split():
                vocabulary.setdefault(word, len(vocabulary))
        rows = np.zeros((len(texts), 256))
        for i, text in enumerate(texts):
            for word in text.split():
                rows[i, vocabulary[word]] += 1
        return rows / np.linalg.norm(rows, axis=1, keepdims=True)

    return encode


def _tiny(folder: Path) -> Path:
    def apple(pattern: str, level: int) -> str:
        return f"apple {pattern} {level}"

    def pen(pattern: str, level: int) -> str:
        return f"pen {pattern} {level}"

    # B1's every instruction is also in the bank, from M1, another trial of the same ALFRED task: its top-1 item
    # has the same condition, target, type and task. Every instruction of B2 is M2's clean control word for word:
    # same task type only (and, for B2's own clean control, the same pattern).
    benchmark = [
        TinyTask("trial_B1", "pick_and_place_simple", "Apple", "pick_and_place_simple-Apple-None-Shelf-1", apple),
        TinyTask(
            "trial_B2",
            "look_at_obj_in_light",
            "Book",
            "look_at_obj_in_light-Book-None-DeskLamp-1",
            lambda p, lv: pen(CLEAN, 0),
        ),
    ]
    memory = [
        TinyTask("trial_M1", "pick_and_place_simple", "Apple", "pick_and_place_simple-Apple-None-Shelf-1", apple),
        TinyTask("trial_M2", "look_at_obj_in_light", "Pen", "look_at_obj_in_light-Pen-None-DeskLamp-1", pen),
    ]
    return write_tiny_dataset(folder, benchmark, memory)


def test_top1_agreement_counts_each_label_per_group() -> None:
    a = QueryLabels("intrusion", "pick_and_place_simple", "Apple", "n1")
    rows = top1_agreement(
        [a, a, QueryLabels(CLEAN, "pick_and_place_simple", "Apple", "n1")],
        [a, QueryLabels("topic_drift", "pick_and_place_simple", "Pen", "n2"), a],
    )
    by_group = {r.group: r for r in rows}
    assert list(by_group) == [ALL_VARIANTS, "intrusion", CLEAN]  # groups without queries are left out
    assert by_group[ALL_VARIANTS].queries == 2
    assert (by_group["intrusion"].same_pattern, by_group["intrusion"].same_target) == (0.5, 0.5)
    assert by_group["intrusion"].same_task_type == 1.0 and by_group["intrusion"].same_alfred_task == 0.5
    assert by_group[CLEAN].same_pattern == 0.0 and by_group[CLEAN].same_target == 1.0
    with pytest.raises(ValueError, match="3 queries but 2"):
        top1_agreement([a, a, a], [a, a])


def _check_tiny_report(report: dict[str, object]) -> None:
    rows = {r["group"]: r for r in report["rows"]}  # type: ignore[attr-defined]
    assert report["queries"] == 32 and report["memory_items"] == 32
    # Over the 30 variants: B1's 15 share everything, B2's 15 only the task type.
    assert rows[ALL_VARIANTS] == {
        "group": ALL_VARIANTS,
        "queries": 30,
        "same_pattern": 0.5,
        "same_target": 0.5,
        "same_task_type": 1.0,
        "same_alfred_task": 0.5,
    }
    for pattern in PATTERN_CONFIGS:
        assert rows[pattern]["queries"] == 6 and rows[pattern]["same_pattern"] == 0.5
    # Both clean controls retrieve a clean control; only B1's is of its own target and task.
    assert (rows[CLEAN]["same_pattern"], rows[CLEAN]["same_target"], rows[CLEAN]["same_alfred_task"]) == (1.0, 0.5, 0.5)


def test_diagnostics_of_a_tiny_bank(tmp_path: Path) -> None:
    report = compute_retrieval(_tiny(tmp_path / "data"), encode=_bag_of_words())
    _check_tiny_report(report)


@pytest.mark.slow
def test_diagnostics_of_a_tiny_bank_with_minilm(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("TALKDEM_CACHE_DIR", str(tmp_path / "cache"))
    report = compute_retrieval(_tiny(tmp_path / "data"))
    assert report["encoder"] == "sentence-transformers/all-MiniLM-L6-v2"
    _check_tiny_report(report)


def test_the_card_fragment_shows_figures_only_for_the_build_they_describe(tmp_path: Path) -> None:
    folder = _tiny(tmp_path / "data")
    absent = memory_bank_section(folder)
    assert MEMORY_RULE in absent and "not computed for this build yet: run `talkdem retrieval`" in absent
    write_retrieval(folder, compute_retrieval(folder, encode=_bag_of_words()))  # type: ignore[arg-type]
    shown = memory_bank_section(folder)
    assert "| All 15 variants | 30 | 50.0% | 50.0% | 100.0% | 50.0% |" in shown
    assert "| Clean controls | 2 | 100.0% | 50.0% | 100.0% | 50.0% |" in shown
    assert "Some queries retrieve an item of their own ALFRED task" in shown  # B1 shares its task with M1
    assert str(tmp_path) not in shown
    # A rebuild changes the files read: the old figures are not shown as this build's.
    bank = folder / "memory_bank" / "train.parquet"
    bank.write_bytes(bank.read_bytes() + b"\0")
    stale = memory_bank_section(folder)
    assert "computed on another build" in stale and "50.0%" not in stale
    retrieval_file(folder).write_text(json.dumps({"rows": "nonsense"}))
    with pytest.raises(ValueError, match="not a retrieval report"):
        memory_bank_section(folder)
