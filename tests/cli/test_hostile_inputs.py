"""Bad input to any command: one line naming the problem and a non-zero exit, never a traceback and never
an exit 0 for a run that did nothing."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from talkdem.cli import main
from talkdem.tasks import load_tasks


def _fails(argv: list[str], capsys: pytest.CaptureFixture[str]) -> str:
    """Run the CLI in this process; return stderr after checking the exit was a clean refusal."""
    try:
        code = main(argv)
    except SystemExit as exit_:  # argparse refuses a bad option value before the command starts
        code = int(exit_.code or 0)
    error = capsys.readouterr().err
    assert code == 2, f"exit {code} for {argv}: {error}"
    assert "Traceback" not in error
    assert error.strip().count("\n") <= 1 or error.startswith("usage:"), error
    return error


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["run", "--limit", "0"], "--limit: must be at least 1, got 0"),
        (["run", "--limit", "-3"], "--limit: must be at least 1, got -3"),
        (["run", "--max-steps", "0"], "--max-steps: must be at least 1"),
        (["run", "--limit", "x"], "'x' is not a whole number"),
        (["run", "--conditions", ","], "no condition in ','"),
        (["run", "--conditions", "intrusion:7"], "the level must be 1, 2 or 3"),
        (["demo", "--tasks", "0"], "--tasks: must be at least 1"),
        (["run", "--backend", "hf", "--base-url", "http://127.0.0.1:9/v1"], "are for --backend openai"),
        (["run", "--backend", "openai", "--model", "m", "--threads", "2"], "--threads applies to the hf and llamacpp"),
        (["build", "--limit", "-1"], "--limit: must be at least 1"),
        (["push", "--repo", "not a repo", "--dry-run"], "is not a Hub repository id"),
        (["report", "x", "--bootstrap", "-5"], "--bootstrap: must be 0 (no intervals) or at least 40"),
        (["leaderboard", "x", "--bootstrap", "-5"], "--bootstrap: must be 0 (no intervals) or at least 40"),
        (["report", "x", "--reference-strategy", "magic"], "unknown strategy 'magic'"),
        (["push", "--repo", "org/name/extra", "--dry-run"], "is not a Hub repository id"),
    ],
)
def test_bad_option_values_are_refused(argv: list[str], message: str, capsys: pytest.CaptureFixture[str]) -> None:
    assert message in _fails(argv, capsys)


def test_out_under_an_existing_file(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    blocker = tmp_path / "file"
    blocker.write_text("")
    plans = tmp_path / "plans.jsonl"
    task = load_tasks("benchmark")[0]
    plans.write_text(json.dumps({"episode_id": f"{task.task_id}:clean:0", "plan": ["done"]}) + "\n")
    error = _fails(["score", str(plans), "--out", str(blocker / "run")], capsys)
    assert "Not a directory" in error and str(blocker) in error


def test_out_that_is_a_file(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    target = tmp_path / "file"
    target.write_text("keep me")
    plans = tmp_path / "plans.jsonl"
    task = load_tasks("benchmark")[0]
    plans.write_text(json.dumps({"episode_id": f"{task.task_id}:clean:0", "plan": ["done"]}) + "\n")
    error = _fails(["score", str(plans), "--out", str(target)], capsys)
    assert "is not a folder" in error or "Not a directory" in error
    assert target.read_text() == "keep me"


def test_a_plan_nested_too_deeply(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    plan = tmp_path / "plan.json"
    plan.write_text("[" * 100_000 + "]" * 100_000)
    task = load_tasks("benchmark")[0]
    assert "nested too deeply" in _fails(["simulate", "--task", task.task_id, "--plan-file", str(plan)], capsys)


def test_an_unreadable_plan_file(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    task = load_tasks("benchmark")[0]
    error = _fails(["simulate", "--task", task.task_id, "--plan-file", str(tmp_path)], capsys)
    assert "cannot read plan file" in error
    error = _fails(["score", str(tmp_path), "--out", str(tmp_path / "run")], capsys)
    assert "cannot read the plan file" in error


def test_a_plan_that_is_a_string(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    plan = tmp_path / "plan.json"
    plan.write_text(json.dumps("find an apple"))
    task = load_tasks("benchmark")[0]
    error = _fails(["simulate", "--task", task.task_id, "--plan-file", str(plan)], capsys)
    assert "a plan must be a list of skill strings" in error and "got a string" in error


def test_a_model_file_that_does_not_exist(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    missing = tmp_path / "no-such-model.gguf"
    error = _fails(
        ["run", "--backend", "llamacpp", "--model", str(missing), "--limit", "1", "--out", str(tmp_path / "r")], capsys
    )
    assert "no-such-model.gguf" in error
    assert not (tmp_path / "r").exists(), "nothing is created before the model loads"


def test_an_unreachable_server(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    argv = [
        "run", "--backend", "openai", "--base-url", "http://127.0.0.1:9/v1", "--model", "m",
        "--planner", "generative", "--limit", "1", "--conditions", "clean", "--out", str(tmp_path / "r"),
        "--no-progress",
    ]  # fmt: skip
    error = _fails(argv, capsys)
    assert "127.0.0.1:9" in error
