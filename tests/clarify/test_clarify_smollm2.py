"""`talkdem run --clarify oracle` with a real small model (SmolLM2-135M): the structure of what is written."""

from __future__ import annotations

from pathlib import Path

import pytest

from talkdem.clarify import QUESTIONS, Slot, oracle_answer
from talkdem.cli import main
from talkdem.runs import read_episodes, read_header
from talkdem.skills import skill_texts
from talkdem.tasks import get_task

pytestmark = pytest.mark.slow


def test_a_real_model_runs_with_an_oracle_person(tmp_path: Path) -> None:
    pytest.importorskip("llama_cpp")
    out = tmp_path / "run"
    command = ["run", "--backend", "llamacpp", "--model", "smollm2", "--model-arg", "threads=1"]
    command += ["--conditions", "clean"]
    command += ["--limit", "1", "--max-steps", "4", "--clarify", "oracle", "--no-progress", "--out", str(out)]
    assert main(command) == 0
    header = read_header(out)
    assert (header.config["clarify"], header.config["clarify_budget"]) == ("oracle", 2)
    (record,) = read_episodes(out)
    assert 1 <= len(record.plan) <= 4 and set(record.plan) <= skill_texts()
    dialogue = record.trace["dialogue"]
    assert len(dialogue) <= 2
    task = get_task(record.task_id)
    for exchange in dialogue:  # whatever the model asked, the oracle answered that slot, clearly
        assert exchange["question"] in QUESTIONS.values() and not exchange["in_pattern"]
        assert exchange["answer"] == oracle_answer(task, Slot(exchange["slot"]))
