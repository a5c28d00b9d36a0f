"""Results files are checked before they are shown, written or uploaded: a results folder is open to
anyone's pull request, so an id that is a path, a count that is markup or a stray credentials file must
not reach the page, the file system outside `--out`, or the Hub."""

from __future__ import annotations

import copy
import json
import shutil
from pathlib import Path
from typing import Any

import pytest
from test_publish import FakeHub, hub  # noqa: F401  (the Hub client stand-in, as a fixture)

from talkdem.cli import main


def _a_record(board: Path) -> dict[str, Any]:
    path = next(p for p in sorted((board / "results").rglob("*.json")) if "planner_A" in str(p))
    record: dict[str, Any] = json.loads(path.read_text())
    return record


def _folder_with(tmp_path: Path, record: dict[str, Any]) -> Path:
    folder = tmp_path / "incoming"
    folder.mkdir(exist_ok=True)
    (folder / "submitted.json").write_text(json.dumps(record))
    return folder


def _leaderboard_fails(folder: Path, out: Path, capsys: pytest.CaptureFixture[str]) -> str:
    assert main(["leaderboard", "--from-results", str(folder), "--out", str(out)]) == 2
    error = capsys.readouterr().err
    assert "Traceback" not in error and error.strip().count("\n") == 0, error
    return error


def test_a_run_id_that_is_a_path_writes_nothing_outside_out(
    board: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    record = _a_record(board)
    record["run_id"] = "x/../../../../escaped/pwned"
    folder = _folder_with(tmp_path, record)
    error = _leaderboard_fails(folder, tmp_path / "deep" / "er" / "out", capsys)
    assert "submitted.json" in error and "run_id" in error
    assert not list(tmp_path.rglob("pwned*")) and not (tmp_path / "escaped").exists()


@pytest.mark.parametrize(
    ("change", "field"),
    [
        (lambda r: r["results"]["talkdem"].update(hazard_cases="<script>alert(1)</script>"), "hazard_cases"),
        (lambda r: r["results"]["talkdem"].update(n_tasks=2.5), "n_tasks"),
        (lambda r: r["results"]["talkdem"].update(n_episodes=True), "n_episodes"),
        (lambda r: r["results"]["talkdem"].update(average_sr=1.7), "average_sr"),
        (lambda r: r["results"]["talkdem_intrusion"].update(retention=-0.1), "talkdem_intrusion.retention"),
        (lambda r: r["results"]["talkdem_intrusion"].update(sr_change_p=float("nan")), "sr_change_p"),
        (lambda r: r["intervals"].update(clean_sr=[0.9, 0.1]), "intervals.clean_sr"),
        (lambda r: r["coverage"].update(tasks=301), "coverage.tasks"),
        (lambda r: r.pop("config"), "config"),
        (lambda r: r["config"].pop("dataset_hash"), "dataset_hash"),
        (lambda r: r["config"].update(model_name=["a"]), "config.model_name"),
        (lambda r: r.update(runtimes={"cpu": "x"}), "runtimes"),
        (lambda r: r.update(runtimes=[{"cpu": "<b>x</b>", "threads": 2}]), "runtimes[0].threads"),
    ],
)
def test_impossible_fields_are_refused_naming_file_and_field(
    board: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str], change: Any, field: str
) -> None:
    record = _a_record(board)
    change(record)
    error = _leaderboard_fails(_folder_with(tmp_path, record), tmp_path / "out", capsys)
    assert "submitted.json" in error and field in error, error
    assert not (tmp_path / "out" / "index.html").exists()


def test_every_record_the_board_writes_passes_the_check(board: Path) -> None:
    from talkdem.leaderboard import ResultsFileError, validate_record

    for path in (board / "results").rglob("*.json"):
        validate_record(json.loads(path.read_text()), str(path))
    with pytest.raises(ResultsFileError, match="run_id"):
        validate_record({**_a_record(board), "run_id": ".."}, "x.json")


def test_markup_in_text_fields_renders_as_text(board: Path, tmp_path: Path) -> None:
    record = _a_record(board)
    record["config"]["run_name"] = record["config"]["model_name"] = "<script>alert(1)</script>"
    record["config"]["strategy"] = '"><img onerror=alert(2)>'
    folder = _folder_with(tmp_path, record)
    assert main(["leaderboard", "--from-results", str(folder), "--out", str(tmp_path / "out")]) == 0
    page = (tmp_path / "out" / "index.html").read_text()
    assert "<script>alert" not in page and "<img" not in page
    assert "&lt;script&gt;alert(1)&lt;/script&gt;" in page


def test_an_empty_results_folder_is_refused(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (tmp_path / "empty").mkdir()
    error = _leaderboard_fails(tmp_path / "empty", tmp_path / "out", capsys)
    assert "no results files" in error and str(tmp_path / "empty") in error


def test_the_leaderboard_command_prints_percent_like_the_page(board: Path, capsys: pytest.CaptureFixture[str]) -> None:
    capsys.readouterr()
    assert main(["leaderboard", "--from-results", str(board / "results"), "--out", str(board.parent / "b2")]) == 0
    out = capsys.readouterr().out
    line = next(line for line in out.splitlines() if "planner-B" in line)
    records = json.loads((board / "leaderboard.json").read_text())
    record = next(r for r in records if "planner-B" in r["config"]["run_name"])
    assert f"average SR {100 * record['results']['talkdem']['average_sr']:.1f}%" in line
    assert "None" not in out


def test_push_uploads_only_valid_results_and_says_what_it_skipped(
    board: Path,
    tmp_path: Path,
    hub: FakeHub,  # noqa: F811
    capsys: pytest.CaptureFixture[str],
) -> None:
    folder = tmp_path / "board"
    shutil.copytree(board, folder)
    (folder / "results" / "creds.json").write_text(json.dumps({"token": "hf_secret"}))
    forged = copy.deepcopy(_a_record(board))
    forged["results"]["talkdem"]["clean_sr"] = 4.0
    (folder / "results" / "planner_A" / "forged.json").write_text(json.dumps(forged))
    (folder / "notes.txt").write_text("private")
    argv = ["push", "--leaderboard", str(folder), "--repo", "org/board", "--results-repo", "org/results"]
    assert main([*argv, "--dry-run"]) == 0
    dry = capsys.readouterr()
    assert "creds.json" not in dry.out and "forged.json" not in dry.out
    assert main(argv) == 0
    err = capsys.readouterr().err
    for name in ("creds.json", "forged.json", "notes.txt"):
        assert f"skipped {folder}" in err and name in err, err
        assert name in dry.err
    sent = [p.name for p in (hub.root).rglob("*") if p.is_file()]
    assert "creds.json" not in sent and "forged.json" not in sent and "notes.txt" not in sent
    assert sum(name.endswith(".json") and name.startswith("results_") for name in sent) == 12  # 6 each
    assert not any("hf_secret" in p.read_text() for p in hub.root.rglob("*") if p.is_file())
