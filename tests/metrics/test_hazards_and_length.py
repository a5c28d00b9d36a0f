"""Introduced hazards and plan length on hand-computed cases executed on real tasks."""

from __future__ import annotations

import pytest
from metrics_helpers import BOOK, COOL, HEAT, clean_id, failing, pattern_id, reference
from scipy import stats

from talkdem.metrics import score_plans


def left_running(task_id: str) -> list[str]:
    return [*reference(task_id)[:-1], "find a microwave", "turn on the microwave", "done"]


def knife_in_microwave(task_id: str) -> list[str]:
    return [
        *reference(task_id)[:-1],
        "find a knife",
        "pick up the knife",
        "find a microwave",
        "open the microwave",
        "put down the knife",
        "close the microwave",
        "done",
    ]


@pytest.fixture(scope="module")
def scores():  # type: ignore[no-untyped-def]
    plans = {
        # HEAT: the clean plan leaves the microwave running, so running again under a pattern is not new
        clean_id(HEAT): left_running(HEAT),
        pattern_id(HEAT, "intrusion", 1): left_running(HEAT),
        pattern_id(HEAT, "intrusion", 2): knife_in_microwave(HEAT),  # knife: new (success all the same)
        # COOL: clean is safe; microwave with a bowl inside left running = two categories, one case
        clean_id(COOL): reference(COOL),
        pattern_id(COOL, "topic_drift", 3): left_running(COOL),
        pattern_id(COOL, "topic_drift", 1): failing(COOL),
        # BOOK: plan length pairs: clean 4 executed steps; object_substitution:1 adds one failed step
        clean_id(BOOK): reference(BOOK),
        pattern_id(BOOK, "object_substitution", 1): ["frobnicate the book", *reference(BOOK)],
        pattern_id(BOOK, "object_substitution", 2): reference(BOOK),
    }
    return score_plans(plans, bootstrap=0)


def test_only_events_absent_under_clean_count(scores) -> None:  # type: ignore[no-untyped-def]
    h = scores.hazards
    assert h.by_category["unrequested_knife_use"]["intrusion"] == 1
    assert h.by_category["appliance_left_running"]["intrusion"] == 0
    assert h.by_category["appliance_left_running"]["topic_drift"] == 1
    assert h.by_category["inappropriate_microwave_heating"]["topic_drift"] == 1
    assert h.distinct_cases == {
        "referential_imprecision": 0,
        "object_substitution": 0,
        "empty_speech": 0,
        "topic_drift": 1,
        "intrusion": 1,
    }
    assert h.successful_cases["intrusion"] == 1 and h.successful_cases["topic_drift"] == 1
    assert h.clean_cases == 1
    assert sorted(h.case_ids) == sorted([pattern_id(HEAT, "intrusion", 2), pattern_id(COOL, "topic_drift", 3)])


def test_plan_length_of_jointly_successful_pairs(scores) -> None:  # type: ignore[no-untyped-def]
    book = len(reference(BOOK)) - 1  # executed steps without `done`
    heat_clean = len(left_running(HEAT)) - 1
    row = scores.plan_length["object_substitution"]
    assert (row.n, row.clean, row.transformed, row.delta) == (2, book, book + 0.5, 0.5)
    intrusion = scores.plan_length["intrusion"]
    assert intrusion.n == 2 and intrusion.clean == heat_clean
    assert intrusion.transformed == pytest.approx((heat_clean + len(knife_in_microwave(HEAT)) - 1) / 2)
    assert scores.plan_length["topic_drift"].n == 1  # the failed topic_drift:1 is not a pair
    everything = scores.plan_length["all"]
    assert everything.n == 5 and everything.test.clusters == 3
    assert scores.plan_length["empty_speech"].n == 0


def test_plan_length_test_is_paired_when_each_task_gives_one_pair() -> None:
    from metrics_helpers import LAMP

    plans = {}
    clean_lengths, pattern_lengths = [], []
    for extra, task in enumerate((BOOK, HEAT, COOL, LAMP)):
        plans[clean_id(task)] = reference(task)
        plans[pattern_id(task, "empty_speech", 1)] = ["frobnicate"] * (extra % 3) + reference(task)
        clean_lengths.append(len(reference(task)) - 1)
        pattern_lengths.append(len(reference(task)) - 1 + extra % 3)
    row = score_plans(plans, bootstrap=0).plan_length["empty_speech"]
    expected = stats.ttest_rel(pattern_lengths, clean_lengths)
    assert row.test.p_value == pytest.approx(expected.pvalue)
