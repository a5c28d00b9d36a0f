"""The evaluate module's optional clarification inputs: question counts, and the plans made without asking."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import pytest
from metrics_helpers import BOOK, LAMP, clean_id, failing, pattern_id, reference

FOLDER = Path(__file__).resolve().parents[2] / "evaluate_talkdem"


@pytest.fixture(scope="module")
def metric() -> Any:
    os.environ.setdefault("HF_HUB_OFFLINE", "1")
    evaluate = pytest.importorskip("evaluate")
    return evaluate.load(str(FOLDER))


def test_question_counts_add_the_clarification_measures(metric: Any) -> None:
    refs = [clean_id(BOOK), pattern_id(BOOK, "intrusion", 1), clean_id(LAMP), pattern_id(LAMP, "intrusion", 1)]
    asked = [reference(BOOK), reference(BOOK), reference(LAMP), reference(LAMP)]
    plain = [reference(BOOK), failing(BOOK), reference(LAMP), failing(LAMP)]
    out = metric.compute(predictions=asked, references=refs, bootstrap=0, questions=[1, 2, 0, 0], without=plain)
    assert out["clarify/sr/intrusion:1"] == 1.0
    assert out["clarify/questions/intrusion:1"] == 1.0
    assert out["clarify/help_rate/all"] == 0.5
    assert out["clarify/gain_per_question/intrusion:1"] == 1.0  # +100 points for one question per episode
    assert out["clarify/unneeded_questions"] == 1.0
    assert out["clarify/gain_per_question/clean"] == 0.0  # half a question per clean episode, no change
    assert out["clarify/retention/clean"] is None  # undefined: NaN becomes None
    plain_out = metric.compute(predictions=asked, references=refs, bootstrap=0)
    assert not any(key.startswith("clarify/") for key in plain_out)


def test_clarification_inputs_must_fit(metric: Any) -> None:
    refs = [clean_id(BOOK)]
    with pytest.raises(ValueError, match="question counts for"):
        metric.compute(predictions=[reference(BOOK)], references=refs, bootstrap=0, questions=[1, 2])
    with pytest.raises(ValueError, match="give `questions`"):
        metric.compute(predictions=[reference(BOOK)], references=refs, bootstrap=0, without=[reference(BOOK)])


def test_the_clean_ids_short_form_counts_its_questions_the_same(metric: Any) -> None:
    asked = [reference(BOOK), reference(BOOK), reference(LAMP), reference(LAMP)]
    plain = [reference(BOOK), failing(BOOK), reference(LAMP), failing(LAMP)]
    outs = []
    for clean in (clean_id, lambda task: f"{task}:clean"):
        refs = [clean(BOOK), pattern_id(BOOK, "intrusion", 1), clean(LAMP), pattern_id(LAMP, "intrusion", 1)]
        outs.append(
            metric.compute(predictions=asked, references=refs, bootstrap=0, questions=[1, 2, 0, 0], without=plain)
        )
    assert outs[0] == outs[1] and outs[1]["clarify/questions/clean"] == 0.5
