"""Run directories: resume after SIGKILL, truncated lines, external plans, sampling."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from talkdem.runs import read_episodes, read_header
from talkdem.runs.external import read_plan_file, record_plan_file
from talkdem.runs.sampling import select_episodes, stratified_task_ids
from talkdem.schema import Condition, parse_conditions
from talkdem.tasks import get_task

SCRIPT = Path(__file__).parent / "run_scripted.py"
ARGS = [
    "run",
    "--backend",
    "scripted",
    "--model",
    "m",
    "--conditions",
    "clean,intrusion:1,topic_drift:2",
    "--limit",
    "3",
    "--no-progress",
]


def _run(out: Path, delay: float) -> subprocess.Popen[bytes]:
    return subprocess.Popen([sys.executable, str(SCRIPT), str(delay), *ARGS, "--out", str(out)])


def _comparable(run_dir: Path) -> list[dict[str, object]]:
    records = [json.loads(line) for line in (run_dir / "episodes.jsonl").read_text().splitlines()]
    for record in records:
        record.pop("timing")
    return records


def test_resume_after_sigkill_matches_an_uninterrupted_run(tmp_path: Path) -> None:
    reference = tmp_path / "uninterrupted"
    assert _run(reference, 0.0).wait(timeout=300) == 0
    assert len(_comparable(reference)) == 9

    killed = tmp_path / "killed"
    process = _run(killed, 0.05)
    episodes = killed / "episodes.jsonl"
    deadline = time.time() + 240
    while time.time() < deadline and (not episodes.exists() or len(episodes.read_text().splitlines()) < 3):
        time.sleep(0.05)
    os.kill(process.pid, signal.SIGKILL)
    process.wait()
    finished = len(episodes.read_text().splitlines())
    assert 3 <= finished < 9, "the kill should land mid-run"
    assert _run(killed, 0.0).wait(timeout=300) == 0
    assert _comparable(killed) == _comparable(reference)


def test_truncated_last_line_is_dropped_and_repaired(tmp_path: Path) -> None:
    run_dir = tmp_path / "run"
    assert _run(run_dir, 0.0).wait(timeout=300) == 0
    path = run_dir / "episodes.jsonl"
    text = path.read_text()
    path.write_text(text + text.splitlines()[0][:40])
    with pytest.warns(UserWarning, match="line 10: truncated last record"):
        assert len(read_episodes(run_dir, repair=True)) == 9
    assert path.read_text() == text


def test_a_corrupt_middle_line_is_an_error_naming_it(tmp_path: Path) -> None:
    run_dir = tmp_path / "run"
    assert _run(run_dir, 0.0).wait(timeout=300) == 0
    path = run_dir / "episodes.jsonl"
    lines = path.read_text().splitlines()
    lines[2] = "{not json"
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(ValueError, match=r"episodes\.jsonl, line 3"):
        read_episodes(run_dir)


def test_resuming_into_a_different_run_is_refused(tmp_path: Path) -> None:
    run_dir = tmp_path / "run"
    assert _run(run_dir, 0.0).wait(timeout=300) == 0
    header = json.loads((run_dir / "header.json").read_text())
    header["strategy"] = "care"
    (run_dir / "header.json").write_text(json.dumps(header))
    result = subprocess.run(
        [sys.executable, str(SCRIPT), "0", *ARGS, "--out", str(run_dir)], capture_output=True, text=True
    )
    assert result.returncode == 2 and "holds a different run" in result.stderr and "strategy" in result.stderr


def test_external_plans_are_executed_and_scored(tmp_path: Path) -> None:
    episodes = select_episodes(parse_conditions("clean,intrusion:2"), 2)
    plan_file = tmp_path / "plans.jsonl"
    rows = [{"episode_id": e.id, "plan": list(get_task(e.task_id).reference_plan)} for e in episodes]
    rows[1]["plan"] = ["find a spaceship", "done"]
    plan_file.write_text("".join(json.dumps(r) + "\n" for r in rows))
    assert record_plan_file(plan_file, tmp_path / "ext", "my-planner") == 4
    records = read_episodes(tmp_path / "ext")
    assert [r.success for r in records] == [True, False, True, True]
    assert records[1].trace["steps"][0]["message"] == "instruction not supported"
    assert read_header(tmp_path / "ext").model["name"] == "my-planner"


@pytest.mark.parametrize(
    ("line", "message"),
    [
        ('{"episode_id": "nope:clean:0", "plan": ["done"]}', "unknown episode id 'nope:clean:0'"),
        ('{"episode_id": "X", "plan": "done"}', "must be a list of skill strings"),
        ("[1, 2]", "expected an object with a string 'episode_id'"),
        ("{oops", "not JSON"),
    ],
)
def test_bad_plan_files_name_the_line(tmp_path: Path, line: str, message: str) -> None:
    path = tmp_path / "plans.jsonl"
    path.write_text(line + "\n")
    with pytest.raises(ValueError, match=message):
        read_plan_file(path)


def test_duplicate_ids_in_a_plan_file(tmp_path: Path) -> None:
    episode = select_episodes(parse_conditions("clean"), 1)[0]
    path = tmp_path / "plans.jsonl"
    path.write_text((json.dumps({"episode_id": episode.id, "plan": ["done"]}) + "\n") * 2)
    with pytest.raises(ValueError, match=f"line 2: duplicate episode id '{episode.id}'"):
        read_plan_file(path)


def test_conditions_and_stratified_sampling() -> None:
    assert len(parse_conditions(None)) == 16
    assert parse_conditions("clean,intrusion") == (
        Condition("clean", 0),
        Condition("intrusion", 1),
        Condition("intrusion", 2),
        Condition("intrusion", 3),
    )
    with pytest.raises(ValueError, match="level must be 1, 2 or 3"):
        parse_conditions("intrusion:4")
    episodes = select_episodes(parse_conditions(None), 6)
    assert len(episodes) == 6 * 16
    task_types = {get_task(e.task_id).task_type for e in episodes}
    assert len(task_types) == 6
    by_task: dict[str, set[Condition]] = {}
    for e in episodes:
        by_task.setdefault(e.task_id, set()).add(e.condition)
    assert all(len(c) == 16 for c in by_task.values()), "every sampled task is run under every condition"
    assert stratified_task_ids(episodes, 3) == stratified_task_ids(list(reversed(episodes)), 3)
