"""`talkdem demo`'s last part: the committed runs of the demo's strategies (`results/paper/`, current data),
re-scored and labelled as recorded runs; without them (an installed wheel) it says so instead of failing."""

from __future__ import annotations

from pathlib import Path

import pytest

from talkdem.cli import demo


def test_the_committed_runs_of_the_demos_strategies_are_rescored(capsys: pytest.CaptureFixture[str]) -> None:
    demo._print_committed_runs(["vanilla", "care"])
    out = capsys.readouterr().out
    assert "== 4. The committed runs (results/paper: recorded runs re-scored now, not run by this demo) ==" in out
    described = [line for line in out.splitlines() if line.startswith("- qwen2.5-coder-0.5b / ")]
    labels = [line.split(":")[0].removeprefix("- ") for line in described]
    assert labels == ["qwen2.5-coder-0.5b / Vanilla", "qwen2.5-coder-0.5b / CARE"]
    assert all("60/300 tasks × 16/16 conditions" in line for line in described), described
    assert "earlier build" not in out  # the current runs ran on the instructions in data/ now
    rows = [line for line in out.splitlines() if line.startswith("| qwen2.5-coder-0.5b |")]
    assert [row.split("|")[2].strip() for row in rows] == ["Vanilla", "CARE"]
    assert "results/paper/report/report.md" in out


def test_without_committed_runs_it_says_so(monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.setattr(demo, "COMMITTED", Path("no-such-results") / "paper")
    demo._print_committed_runs(["vanilla"])
    assert "no committed runs in this installation" in capsys.readouterr().out
