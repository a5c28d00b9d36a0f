"""The evaluate module checks its inputs as the caller gave them: `evaluate` casts them through the features
first, and a nested step `[["find a box"]]` would reach the metric as the one skill "['find a box']"."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import pytest
from metrics_helpers import BOOK, LAMP, clean_id, reference

from talkdem.metrics import ScoringInputError

FOLDER = Path(__file__).resolve().parents[2] / "evaluate_talkdem"


@pytest.fixture(scope="module")
def metric() -> Any:
    os.environ.setdefault("HF_HUB_OFFLINE", "1")
    evaluate = pytest.importorskip("evaluate")
    return evaluate.load(str(FOLDER))


def test_a_nested_step_is_refused_naming_its_id(metric: Any) -> None:
    nested = [["find a box"], *reference(LAMP)[1:]]
    with pytest.raises(ScoringInputError, match="lists of skill strings") as refused:
        metric.compute(predictions=[reference(BOOK), nested], references=[clean_id(BOOK), clean_id(LAMP)])
    assert refused.value.ids == (clean_id(LAMP),)
    with pytest.raises(ScoringInputError, match=clean_id(LAMP)):
        metric.add_batch(predictions=[nested], references=[clean_id(LAMP)])
    with pytest.raises(ScoringInputError, match=clean_id(LAMP)):
        metric.add(prediction=[3, "done"], reference=clean_id(LAMP))


def test_plans_given_as_strings_and_impossible_bootstrap_counts(metric: Any) -> None:
    with pytest.raises(ScoringInputError, match="predictions must be a list"):
        metric.compute(predictions="find a box", references=[clean_id(LAMP)])
    with pytest.raises(ValueError, match=r"bootstrap must be a whole number .* got 2\.5"):
        metric.compute(predictions=[reference(BOOK)], references=[clean_id(BOOK)], bootstrap=2.5)
    good = metric.compute(predictions=[reference(BOOK)], references=[clean_id(BOOK)], bootstrap=0)
    assert good["success_rate/clean"] == 1.0
