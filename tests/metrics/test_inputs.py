"""Bad input raises an error naming the offending ids; unknown skills are failed steps, not errors."""

from __future__ import annotations

import pytest
from metrics_helpers import BOOK, LAMP, clean_id, pattern_id, reference

from talkdem.metrics import ScoringInputError, compute_scores, execute_plans, score_plans, score_predictions


def test_empty_input() -> None:
    with pytest.raises(ScoringInputError, match="empty"):
        score_plans({})
    with pytest.raises(ScoringInputError, match="empty"):
        score_predictions([], [])


def test_unknown_ids_are_named() -> None:
    with pytest.raises(ScoringInputError, match="unknown instruction ids") as info:
        score_plans({clean_id(BOOK): reference(BOOK), "nope:clean:0": [], f"{BOOK}:intrusion:4": []})
    assert info.value.ids == ("nope:clean:0", f"{BOOK}:intrusion:4")


def test_duplicate_ids_are_named() -> None:
    with pytest.raises(ScoringInputError, match="duplicate") as info:
        score_predictions([reference(BOOK)] * 3, [clean_id(BOOK), clean_id(LAMP), clean_id(BOOK)])
    assert info.value.ids == (clean_id(BOOK),)
    with pytest.raises(ScoringInputError, match="duplicate") as info:  # the short and long clean ids
        score_plans({clean_id(BOOK): reference(BOOK), f"{BOOK}:clean": reference(BOOK)})
    assert set(info.value.ids) == {clean_id(BOOK), f"{BOOK}:clean"}


@pytest.mark.parametrize("plan", ["find a book", None, ["find a book", 3], [["find a book"]], 42])
def test_plans_that_are_not_lists_of_strings(plan: object) -> None:
    with pytest.raises(ScoringInputError, match="lists of skill strings") as info:
        score_plans({clean_id(BOOK): plan, clean_id(LAMP): reference(LAMP)})  # type: ignore[dict-item]
    assert info.value.ids == (clean_id(BOOK),)


def test_mismatched_lengths() -> None:
    with pytest.raises(ScoringInputError, match="differ in length") as info:
        score_predictions([reference(BOOK)], [clean_id(BOOK), clean_id(LAMP)])
    assert info.value.ids == (clean_id(LAMP),)


def test_pattern_without_clean_twin_when_retention_is_asked() -> None:
    plans = {clean_id(BOOK): reference(BOOK), pattern_id(LAMP, "intrusion", 2): reference(LAMP)}
    with pytest.raises(ScoringInputError, match="no clean twin") as info:
        score_plans(plans)
    assert info.value.ids == (pattern_id(LAMP, "intrusion", 2),)
    scores = score_plans(plans, retention=False, bootstrap=0)
    assert scores.retention is None and scores.success_rate["intrusion:2"] == 1.0


def test_unknown_skills_are_failed_steps() -> None:
    plans = {clean_id(BOOK): ["fly to the moon", *reference(BOOK)], clean_id(LAMP): ["dance"]}
    scores = score_plans(plans, bootstrap=0)
    assert scores.success_rate["clean"] == 0.5
    by_id = {e.instruction_id: e for e in scores.episodes}
    assert by_id[clean_id(LAMP)].trace is not None
    assert by_id[clean_id(LAMP)].trace.steps[0].message == "instruction not supported"


def test_pairs_by_id_not_position() -> None:
    a = score_predictions([reference(BOOK), ["done"]], [clean_id(BOOK), clean_id(LAMP)], bootstrap=0)
    b = score_predictions([["done"], reference(BOOK)], [clean_id(LAMP), clean_id(BOOK)], bootstrap=0)
    assert a.flat() == b.flat()


def test_by_default_retention_is_left_out_when_a_pattern_has_no_clean_twin() -> None:
    # what `talkdem report` does for a run of pattern conditions only: success rates stand, retention is
    # None and the episodes that left it out are named (the report says so); a full pairing still measures it
    orphan = pattern_id(LAMP, "intrusion", 2)
    results = execute_plans({clean_id(BOOK): reference(BOOK), orphan: reference(LAMP)})
    scores = compute_scores(results, bootstrap=0)
    assert scores.retention is None and scores.without_clean_twin == (orphan,)
    assert scores.success_rate["intrusion:2"] == 1.0
    paired = execute_plans({clean_id(LAMP): reference(LAMP), orphan: reference(LAMP)})
    scores = compute_scores(paired, bootstrap=0)
    assert scores.retention is not None and scores.retention["intrusion:2"] == 1.0 and not scores.without_clean_twin
    with pytest.raises(ScoringInputError, match="call with retention=False"):
        compute_scores(results, retention=True, bootstrap=0)
