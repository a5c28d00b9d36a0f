"""`talkdem score` names the agent (name, model, strategy, version) and flags steps outside the vocabulary."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from talkdem.cli import main
from talkdem.runs import read_episodes, read_header
from talkdem.runs.sampling import select_episodes
from talkdem.schema import parse_conditions
from talkdem.tasks import get_task


def test_score_records_the_agent_and_counts_out_of_vocabulary_steps(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    first, second = select_episodes(parse_conditions("clean"), 2)
    plans = tmp_path / "plans.jsonl"
    rows = [
        # the short clean id is the metric's rule too: stored under the long form
        {"episode_id": f"{first.task_id}:clean", "plan": ["teleport", *get_task(first.task_id).reference_plan]},
        {"episode_id": second.id, "plan": ["find the moon", "fly", "done"]},
    ]
    plans.write_text("".join(json.dumps(r) + "\n" for r in rows))
    command = ["score", str(plans), "--out", str(tmp_path / "run"), "--name", "toy-agent"]
    command += ["--model", "gpt-x", "--strategy", "react-ish", "--version", "2.1"]
    assert main(command) == 0
    out = capsys.readouterr().out
    assert "3 steps in 2 episodes name no skill" in out
    header = read_header(tmp_path / "run")
    assert header.model == {"backend": "external", "name": "toy-agent", "revision": "2.1"}
    assert header.strategy == "react-ish"
    assert header.config["agent"] == {"name": "toy-agent", "model": "gpt-x", "strategy": "react-ish", "version": "2.1"}
    records = {r.episode_id: r for r in read_episodes(tmp_path / "run")}
    assert set(records) == {first.id, second.id}
    assert records[first.id].success  # the failed step does not end the episode
    assert [s["ok"] for s in records[second.id].trace["steps"]] == [False, False, True]


def test_a_plan_file_naming_one_instruction_twice_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    (first,) = select_episodes(parse_conditions("clean"), 1)
    plans = tmp_path / "plans.jsonl"
    rows = [{"episode_id": first.id, "plan": ["done"]}, {"episode_id": f"{first.task_id}:clean", "plan": ["done"]}]
    plans.write_text("".join(json.dumps(r) + "\n" for r in rows))
    assert main(["score", str(plans), "--out", str(tmp_path / "run")]) == 2
    assert f"line 2: duplicate episode id '{first.id}'" in capsys.readouterr().err
