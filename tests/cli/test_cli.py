"""The `talkdem` command line: contracts of `tasks`, `select --saved`, and a light start."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from talkdem.cli import main


def test_tasks_jsonl_has_the_contract_fields(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["tasks", "--set", "memory", "--format", "jsonl"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert len(lines) == 100
    record = json.loads(lines[0])
    for key in ("task_id", "task_type", "floor_plan", "instruction", "reference_plan", "scene_objects", "pddl_params"):
        assert key in record
    assert record["reference_plan"][-1] == "done"
    assert isinstance(record["scene_objects"], list) and record["scene_objects"]


def test_tasks_table_lists_300_benchmark_tasks(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["tasks"]) == 0
    assert capsys.readouterr().out.rstrip().endswith("300 benchmark tasks")


def test_select_saved_prints_the_diversity_table(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["select", "--saved"]) == 0
    out = capsys.readouterr().out
    assert "| pick_cool_then_place_in_recep | 106 |" in out


def test_bad_set_name_is_rejected(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as caught:
        main(["tasks", "--set", "training"])
    assert caught.value.code == 2
    assert "invalid choice: 'training'" in capsys.readouterr().err


def test_help_and_tasks_do_not_import_heavy_libraries() -> None:
    code = (
        "import sys\n"
        "from talkdem.cli import main\n"
        "main(['tasks', '--format', 'jsonl'])\n"
        "heavy = [m for m in ('torch', 'transformers', 'datasets', 'evaluate', 'sentence_transformers') "
        "if m in sys.modules]\n"
        "print('HEAVY', heavy, file=sys.stderr)\n"
    )
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert "HEAVY []" in result.stderr
