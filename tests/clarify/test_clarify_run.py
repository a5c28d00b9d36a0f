"""`talkdem run --clarify` end to end with the clarifying test model: header, records, resume, old files."""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import pytest
from clarify_lm import ClarifyingLM

from talkdem.clarify import Slot, oracle_answer
from talkdem.cli import main
from talkdem.llm.interface import registry
from talkdem.runs import read_episodes, read_header
from talkdem.tasks import get_task

SCRIPT = ["ask which object to use", "ask where to put it", "find an apple", "pick up the apple", "done"]


class _Clarifying(ClarifyingLM):
    def __init__(self, model: str, **_: object) -> None:
        super().__init__(SCRIPT)


if "clarifying" not in registry.BACKENDS:
    registry.BACKENDS.register("clarifying", _Clarifying)

ARGS = ["run", "--backend", "clarifying", "--model", "m", "--limit", "2", "--no-progress"]
CONDITIONS = ["--conditions", "clean,object_substitution:1"]


def test_in_pattern_run_records_the_dialogue_and_the_header_says_how(tmp_path: Path) -> None:
    out = tmp_path / "run"
    assert main([*ARGS, *CONDITIONS, "--clarify", "in-pattern", "--out", str(out)]) == 0
    header = read_header(out)
    assert (header.config["clarify"], header.config["clarify_budget"]) == ("in-pattern", 2)
    assert header.config["clarify_generator"].startswith("rules/")
    records = read_episodes(out)
    assert len(records) == 4
    for record in records:
        dialogue = record.trace["dialogue"]
        assert [(e["step"], e["slot"]) for e in dialogue] == [(0, "object"), (0, "destination")]
        assert not any(step.startswith("ask") for step in record.plan)
        clear = oracle_answer(get_task(record.task_id), Slot.OBJECT)
        if record.pattern == "clean":
            assert [e["in_pattern"] for e in dialogue] == [False, False]
            assert dialogue[0]["answer"] == clear
        else:
            assert dialogue[0]["in_pattern"] and dialogue[0]["answer"] != clear


def test_resuming_with_another_answer_mode_is_refused(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "run"
    assert main([*ARGS, "--conditions", "clean", "--clarify", "oracle", "--out", str(out)]) == 0
    assert main([*ARGS, "--conditions", "clean", "--clarify", "in-pattern", "--out", str(out)]) == 2
    assert "config.clarify: 'oracle' there, 'in-pattern' now" in capsys.readouterr().err
    assert (
        main([*ARGS, "--conditions", "clean", "--clarify", "oracle", "--clarify-budget", "1", "--out", str(out)]) == 2
    )


def test_a_budget_without_clarification_is_one_line(capsys: pytest.CaptureFixture[str]) -> None:
    assert main([*ARGS, "--conditions", "clean", "--clarify-budget", "3", "--out", "/nonexistent/x"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--clarify-budget applies with --clarify" in err


def test_runs_without_clarification_are_unchanged_and_older_headers_resume(tmp_path: Path) -> None:
    out = tmp_path / "run"
    assert main([*ARGS, "--conditions", "clean", "--limit", "1", "--out", str(out)]) == 0
    record = read_episodes(out)[0]
    assert "dialogue" not in record.trace
    assert not any(step.startswith("ask") for step in record.plan)  # the questions were not offered
    # A header written before clarification existed: it asked nothing, so a run without it resumes silently.
    path = out / "header.json"
    header = json.loads(path.read_text())
    del header["config"]["clarify"], header["config"]["clarify_budget"]
    path.write_text(json.dumps(header))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert main([*ARGS, "--conditions", "clean", "--limit", "2", "--out", str(out)]) == 0
    assert len(read_episodes(out)) == 2


def test_a_sweep_spec_sets_clarification_for_its_runs(tmp_path: Path) -> None:
    from talkdem.sweeps import load_sweep

    spec = tmp_path / "sweep.yaml"
    spec.write_text(
        f"out: {tmp_path / 'out'}\nmodels: [smollm2-135m-instruct]\nstrategies: [vanilla]\n"
        "conditions: [clean]\ntasks: 1\nplanner: {clarify: in-pattern, clarify_budget: 3}\n"
    )
    (run,) = load_sweep(spec).runs
    command = run.command()
    assert command[command.index("--clarify") + 1] == "in-pattern"
    assert command[command.index("--clarify-budget") + 1] == "3"
