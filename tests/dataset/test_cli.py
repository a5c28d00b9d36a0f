"""`talkdem verify` and the command registry."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from talkdem.cli import build_parser, main

POTATO = "trial_T20190909_152050_792044"


def run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, dict[str, object]]:
    code = main(list(argv))
    return code, json.loads(capsys.readouterr().out)


def test_verify_passing(capsys: pytest.CaptureFixture[str]) -> None:
    code, out = run(
        capsys,
        "verify",
        "--task",
        POTATO,
        "--pattern",
        "clean",
        "--text",
        "Hi! Could you put a heated potato on the counter?",
    )
    assert code == 0 and out == {"passed": True, "failed_checks": []}


def test_verify_failing(capsys: pytest.CaptureFixture[str]) -> None:
    text = "Hi! Could you put a heated potato on the counter? The television is new."
    code, out = run(capsys, "verify", "--task", POTATO, "--pattern", "topic_drift", "--level", "1", "--text", text)
    assert code == 0 and out["passed"] is False and "scene_objects" in out["failed_checks"]


def test_verify_unknown_task_and_pattern(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["verify", "--task", "trial_nope", "--pattern", "clean", "--text", "hi"]) == 2
    assert main(["verify", "--task", POTATO, "--pattern", "mumbling", "--level", "1", "--text", "hi"]) == 2
    assert "unknown pattern" in capsys.readouterr().err


def test_new_commands_are_registered() -> None:
    parser = build_parser()
    for command in ("build", "verify", "markers", "push"):
        assert parser.parse_args(_minimal(command)).command == command


def _minimal(command: str) -> list[str]:
    return {
        "build": ["build"],
        "verify": ["verify", "--task", "t", "--pattern", "clean", "--text", "x"],
        "markers": ["markers"],
        "push": ["push", "--repo", "o/n"],
    }[command]


def test_partial_build_refuses_the_shipped_dataset_and_writes_elsewhere(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["build", "--limit", "1", "--no-progress"]) == 2
    assert "--out" in capsys.readouterr().err
    out = tmp_path / "smoke"
    code = main(["build", "--limit", "1", "--out", str(out), "--checkpoint", str(out) + ".ckpt", "--no-progress"])
    stats = json.loads(capsys.readouterr().out)
    assert code == 0 and stats["counts"] == {"tasks": 1, "instructions": 16, "memory_tasks": 1, "memory_items": 16}


def test_build_refuses_to_replace_data_with_other_settings(capsys: pytest.CaptureFixture[str]) -> None:
    from talkdem.paths import repo_root

    stats = repo_root() / "data" / "build_stats.json"
    before = stats.stat().st_mtime_ns
    assert main(["build", "--seed", "3", "--no-progress"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("talkdem build: data/ was built with other settings (--seed 0 there, 3 now")
    assert "--new-settings" in err and "\n" not in err
    assert stats.stat().st_mtime_ns == before
