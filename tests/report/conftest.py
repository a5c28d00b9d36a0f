"""Make `metrics_helpers.py` (in tests/metrics) and `browser_helpers.py` (in tests/leaderboard) importable:
with --import-mode=importlib, test folders are not put on sys.path. And `mixed_runs`/`report`: runs of
different kinds and coverage (a model given as a path, an all-zero run, names with `|`, a newline, or
differing only in punctuation, the oracle) and their report folder."""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent.parent / "metrics"))
sys.path.insert(0, str(Path(__file__).parent.parent / "leaderboard"))

import pytest
from metrics_helpers import BOOK, COOL, HEAT, LAMP, clean_id, failing, pattern_id, reference, write_run

from talkdem.report import ScoredRun, score_runs, write_report
from talkdem.schema import PATTERN_CONFIGS

TASKS = (BOOK, LAMP, HEAT, COOL)


def _plans(solve: int, tasks: tuple[str, ...] = TASKS) -> dict[str, list[str]]:
    """Reference plans for levels up to `solve` (clean is level 0); failing plans above."""
    out = {clean_id(t): reference(t) if solve >= 0 else failing(t) for t in tasks}
    for task in tasks:
        for pattern in PATTERN_CONFIGS:
            for level in (1, 2, 3):
                out[pattern_id(task, pattern, level)] = reference(task) if level <= solve else failing(task)
    return out


@pytest.fixture(scope="session")
def mixed_runs(tmp_path_factory: pytest.TempPathFactory) -> list[ScoredRun]:
    from talkdem.instructions import load_instructions
    from talkdem.runs.oracle import write_oracle_run

    root = tmp_path_factory.mktemp("mixed")
    model = str(root / "weights" / "Tiny.Q8_0.gguf")  # a path on this machine
    dirs = [
        write_run(root / "a", _plans(2), model=model, strategy="vanilla"),
        write_run(root / "b", _plans(3), model=model, strategy="care"),
        write_run(root / "zero", _plans(-1), model=model, strategy="cot"),  # every rate 0
        write_run(root / "pipe", _plans(1, (BOOK,)), model="my|model\nv2", strategy="vanilla"),
        write_run(root / "sp", _plans(1, (BOOK,)), model="my model", strategy="vanilla"),
        write_run(root / "us", _plans(2, (BOOK,)), model="my_model", strategy="vanilla"),
    ]
    write_oracle_run([i for i in load_instructions() if i.task_id == BOOK], root / "oracle")
    return score_runs([*dirs, root / "oracle"], bootstrap=100)


@pytest.fixture(scope="session")
def report(mixed_runs: list[ScoredRun], tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("report") / "report"
    files = write_report(mixed_runs, out)
    assert files.html == out / "report.html"
    return out
