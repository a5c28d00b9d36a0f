"""`talkdem score` adds the plans of a second file to a run of its own (docs/runs.md's workflow: score what
you have, score more later), keeping what is there; a changed plan for an episode already scored, or
another system's run, is refused."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from talkdem.cli import main
from talkdem.runs import read_episodes, read_header
from talkdem.runs.sampling import select_episodes
from talkdem.schema import parse_conditions
from talkdem.tasks import get_task


def _plan_file(path: Path, episodes: list[tuple[str, list[str]]]) -> Path:
    path.write_text("".join(json.dumps({"episode_id": e, "plan": p}) + "\n" for e, p in episodes))
    return path


def test_a_second_plan_file_adds_its_episodes(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    chosen = select_episodes(parse_conditions("clean,intrusion:2"), 2)
    plans = [(e.id, list(get_task(e.task_id).reference_plan)) for e in chosen]
    first = _plan_file(tmp_path / "first.jsonl", plans[:2])
    second = _plan_file(tmp_path / "second.jsonl", plans[1:])  # one overlaps, with the same plan
    run = tmp_path / "run"
    assert main(["score", str(first), "--out", str(run), "--name", "mine"]) == 0
    before = (run / "episodes.jsonl").read_text()
    assert main(["score", str(second), "--out", str(run), "--name", "mine"]) == 0
    out = capsys.readouterr().out
    assert f"{run}: 2 episodes executed and scored, 2 already in the run (4 in all)" in out
    assert (run / "episodes.jsonl").read_text().startswith(before)  # nothing rewritten
    assert sorted(r.episode_id for r in read_episodes(run)) == sorted(e for e, _ in plans)
    header = read_header(run)
    assert header.config["planned_episodes"] == 4 and header.config["plans"] == "first.jsonl, second.jsonl"
    assert main(["report", str(run), "--out", str(tmp_path / "rep"), "--no-plots", "--bootstrap", "0"]) == 0


def test_a_changed_plan_or_another_system_is_refused(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (episode,) = select_episodes(parse_conditions("clean"), 1)
    run = tmp_path / "run"
    good = list(get_task(episode.task_id).reference_plan)
    assert main(["score", str(_plan_file(tmp_path / "a.jsonl", [(episode.id, good)])), "--out", str(run)]) == 0
    before = (run / "episodes.jsonl").read_bytes()
    changed = _plan_file(tmp_path / "b.jsonl", [(episode.id, ["done"])])
    assert main(["score", str(changed), "--out", str(run)]) == 2
    assert "already in the run with another plan" in capsys.readouterr().err
    assert main(["score", str(tmp_path / "a.jsonl"), "--out", str(run), "--name", "someone-else"]) == 2
    assert (run / "episodes.jsonl").read_bytes() == before
