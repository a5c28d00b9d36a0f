"""Viewer fixtures: the committed runs of the default model under Vanilla and CARE (`results/paper/`) loaded
once, their error sample, and the viewer written from them. `browser_helpers.py` (tests/leaderboard) and
`metrics_helpers.py` (tests/metrics) are made importable: with --import-mode=importlib test folders are not on
sys.path."""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent.parent / "leaderboard"))
sys.path.insert(0, str(Path(__file__).parent.parent / "metrics"))
sys.path.insert(0, str(Path(__file__).parent))

import pytest
from viewer_browser import COMMITTED

from talkdem.viewer import ErrorSample, ViewedRun, ViewerFiles, load_runs, sample_errors, write_viewer


@pytest.fixture(scope="session")
def committed_runs() -> list[ViewedRun]:
    return load_runs(list(COMMITTED))


@pytest.fixture(scope="session")
def committed_sample(committed_runs: list[ViewedRun]) -> ErrorSample:
    return sample_errors(committed_runs, 3, seed=7)


@pytest.fixture(scope="session")
def committed_viewer(
    committed_runs: list[ViewedRun], committed_sample: ErrorSample, tmp_path_factory: pytest.TempPathFactory
) -> ViewerFiles:
    return write_viewer(committed_runs, tmp_path_factory.mktemp("viewer") / "viewer", sample=committed_sample.to_json())
