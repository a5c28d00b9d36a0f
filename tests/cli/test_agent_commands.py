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


@pytest.mark.parametrize(
    ("conditions", "message"),
    [
        ("clean:1", "condition 'clean:1': clean has no levels (write clean)"),
        ("clean:3", "condition 'clean:3': clean has no levels"),
        ("clean:", "condition 'clean:': clean has no levels"),
        ("intrusion:3,clean:x", "condition 'clean:x': clean has no levels"),
        ("intrusion:0", "condition 'intrusion:0': the level must be 1, 2 or 3"),
        ("intrusion:4", "condition 'intrusion:4': the level must be 1, 2 or 3"),
        ("intrusion:", "condition 'intrusion:': the level must be 1, 2 or 3"),
        ("shouting:1", "unknown condition 'shouting:1': expected clean or one of"),
        ("shouting", "unknown condition 'shouting': expected clean or one of"),  # as written, not 'shouting:1'
        ("", "no condition in '': expected e.g. clean,intrusion:3,topic_drift"),
        (" , ", "no condition in ' , '"),
    ],
)
@pytest.mark.parametrize("command", ["episodes", "run"])
def test_a_condition_that_selects_nothing_it_says_is_refused(
    command: str, conditions: str, message: str, capsys: pytest.CaptureFixture[str]
) -> None:
    # `run` reads --conditions through the same parser; it must refuse before loading any model
    assert main([command, "--conditions", conditions, "--limit", "1"]) == 2
    error = capsys.readouterr().err
    assert error.count("\n") == 1 and message in error and "unexpected" not in error


@pytest.mark.parametrize(
    ("conditions", "same_as"),
    [
        ("clean,clean", "clean"),  # a condition named twice is selected once
        ("intrusion,intrusion:3", "intrusion"),
        ("clean,,intrusion:3,", "clean,intrusion:3"),  # empty parts are skipped
        ("clean:0", "clean"),  # the long form instruction ids use
    ],
)
def test_repeated_and_empty_parts_select_each_episode_once(
    conditions: str, same_as: str, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["episodes", "--limit", "2", "--conditions", conditions]) == 0
    ids = [json.loads(line)["episode_id"] for line in capsys.readouterr().out.splitlines()]
    assert len(ids) == len(set(ids)) and ids == [i.id for i in select_episodes(parse_conditions(same_as), 2)]
