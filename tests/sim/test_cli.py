"""`talkdem simulate`: the issue's JSON contract and its error exits."""

from __future__ import annotations

import io
import json
from pathlib import Path

import pytest
from helpers import first_task

from talkdem.cli import main


def test_simulate_prints_the_contract(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    task = first_task("pick_heat_then_place_in_recep")
    plan_file = tmp_path / "plan.json"
    plan_file.write_text(json.dumps(list(task.reference_plan)))
    assert main(["simulate", "--task", task.task_id, "--plan-file", str(plan_file)]) == 0
    out = json.loads(capsys.readouterr().out)
    assert set(out) == {"task_id", "success", "steps", "hazards", "goal_conditions"}
    assert out["success"] is True and out["hazards"] == []
    assert out["steps"][0] == {"skill": task.reference_plan[0], "ok": True, "message": ""}
    assert out["goal_conditions"]["met"] == out["goal_conditions"]["total"] > 0


def test_simulate_reads_standard_input(monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    task = first_task("pick_and_place_simple")
    monkeypatch.setattr("sys.stdin", io.StringIO('["find a unicorn", "done"]'))
    assert main(["simulate", "--task", task.task_id, "--plan-file", "-"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["success"] is False
    assert out["steps"][0] == {"skill": "find a unicorn", "ok": False, "message": "instruction not supported"}


@pytest.mark.parametrize("content", ['{"plan": []}', "[1, 2]", "not json"])
def test_bad_plan_files_exit_nonzero(tmp_path: Path, content: str, capsys: pytest.CaptureFixture[str]) -> None:
    plan_file = tmp_path / "plan.json"
    plan_file.write_text(content)
    task = first_task("pick_and_place_simple")
    assert main(["simulate", "--task", task.task_id, "--plan-file", str(plan_file)]) != 0
    assert "list of skill strings" in capsys.readouterr().err


def test_unknown_task_exits_nonzero(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    plan_file = tmp_path / "plan.json"
    plan_file.write_text('["done"]')
    assert main(["simulate", "--task", "trial_nope", "--plan-file", str(plan_file)]) != 0
    assert "unknown task id" in capsys.readouterr().err
