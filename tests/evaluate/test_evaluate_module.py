"""The evaluate module: loads offline from the folder, its doctests run, and it agrees with the core and
the CLI report on the same plans."""

from __future__ import annotations

import doctest
import importlib.util
import json
import os
from pathlib import Path
from typing import Any

import pytest
from metrics_helpers import BOOK, COOL, HEAT, LAMP, clean_id, failing, pattern_id, reference, write_run

from talkdem.cli import main
from talkdem.metrics import score_plans
from talkdem.schema import PATTERN_CONFIGS

FOLDER = Path(__file__).resolve().parents[2] / "evaluate_talkdem"


def plans() -> dict[str, list[str]]:
    out = {clean_id(t): reference(t) for t in (BOOK, LAMP, HEAT, COOL)}
    out[clean_id(COOL)] = failing(COOL)
    for index, task in enumerate((BOOK, LAMP, HEAT, COOL)):
        for p_index, pattern in enumerate(PATTERN_CONFIGS):
            for level in (1, 2, 3):
                fails = (index + p_index + level) % 3 == 0
                out[pattern_id(task, pattern, level)] = failing(task) if fails else reference(task)
    out[pattern_id(HEAT, "intrusion", 2)] = [*reference(HEAT)[:-1], "find a microwave", "turn on the microwave", "done"]
    return out


@pytest.fixture(scope="module")
def metric() -> Any:
    os.environ.setdefault("HF_HUB_OFFLINE", "1")
    evaluate = pytest.importorskip("evaluate")
    return evaluate.load(str(FOLDER))


def test_doctests_of_the_module_run() -> None:
    spec = importlib.util.spec_from_file_location("evaluate_talkdem_doctest", FOLDER / "evaluate_talkdem.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    cwd = os.getcwd()
    os.chdir(FOLDER.parent)  # the examples load "evaluate_talkdem" from the checkout root
    try:
        result = doctest.testmod(module, verbose=False)
    finally:
        os.chdir(cwd)
    assert result.attempted >= 5 and result.failed == 0


def test_metric_card_and_features(metric: Any) -> None:
    assert "retention" in metric.description and metric.citation.startswith("@inproceedings")
    assert set(metric.features) == {"predictions", "references"}
    assert (FOLDER / "README.md").read_text().startswith("---")


def test_evaluate_core_and_cli_report_agree(metric: Any, tmp_path: Path) -> None:
    chosen = plans()
    ids = sorted(chosen, reverse=True)  # a different order from the dict: pairing is by id
    computed = metric.compute(predictions=[chosen[i] for i in ids], references=ids, bootstrap=0)
    core = score_plans(chosen, bootstrap=0).flat()
    assert computed == core

    run_dir = write_run(tmp_path / "run", chosen)
    assert main(["report", str(run_dir), "--out", str(tmp_path / "out"), "--bootstrap", "0", "--no-plots"]) == 0
    report = json.loads((tmp_path / "out" / "scores" / "tiny-model_Vanilla.json").read_text())
    for key, value in report["success_rate"].items():
        assert computed[f"success_rate/{key}"] == value
    for key, value in report["retention"].items():
        assert computed[f"retention/{key}"] == value
    assert computed["hazard_cases"] == report["hazards"]["total_cases"] == 1
    assert computed["plan_length/all/n"] == report["plan_length"]["all"]["n"]
    assert computed["plan_length/all/delta"] == report["plan_length"]["all"]["delta"]
    for error_type, count in report["errors"].items():
        assert computed[f"errors/{error_type}"] == count
    assert computed["success_rate/clean"] == 0.75


def test_bad_input_through_evaluate(metric: Any) -> None:
    with pytest.raises(ValueError, match="duplicate"):
        metric.compute(predictions=[reference(BOOK)] * 2, references=[clean_id(BOOK)] * 2)
    with pytest.raises(ValueError, match="unknown instruction ids"):
        metric.compute(predictions=[reference(BOOK)], references=["nope:clean:0"])
    with pytest.raises(ValueError):
        metric.compute(predictions=[reference(BOOK)], references=[clean_id(BOOK), clean_id(LAMP)])
