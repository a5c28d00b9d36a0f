"""`talkdem episodes` lists exactly what `talkdem run` plans; `talkdem skills` the vocabulary."""

from __future__ import annotations

import json

import pytest

from talkdem.cli import main
from talkdem.runs.sampling import select_episodes
from talkdem.schema import parse_conditions
from talkdem.skills import vocabulary


def test_episodes_are_the_selection_of_talkdem_run(capsys: pytest.CaptureFixture[str]) -> None:
    conditions = "clean,intrusion:3,topic_drift"
    assert main(["episodes", "--limit", "7", "--conditions", conditions]) == 0
    rows = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
    expected = select_episodes(parse_conditions(conditions), 7)
    assert [r["episode_id"] for r in rows] == [i.id for i in expected] and len(rows) == 7 * 5
    assert [r["instruction"] for r in rows] == [i.text for i in expected]


def test_skills_are_the_vocabulary(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["skills"]) == 0
    assert capsys.readouterr().out.splitlines() == [s.text for s in vocabulary()]
    assert main(["skills", "--format", "jsonl"]) == 0
    rows = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
    assert len(rows) == 214 and rows[0] == {"skill": "done", "verb": "done", "object_type": ""}


def test_a_bad_selection_is_one_line(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["episodes", "--conditions", "intrusion:9"]) == 2
    assert capsys.readouterr().err.count("\n") == 1
