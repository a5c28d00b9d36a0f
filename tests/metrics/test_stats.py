"""The paired t-tests against scipy, the clustered test by hand, bootstrap determinism, stars."""

from __future__ import annotations

import math

import numpy as np
import pytest
from metrics_helpers import BOOK, COOL, HEAT, LAMP, clean_id, failing, pattern_id, reference
from scipy import stats

from talkdem.metrics import (
    bootstrap_ci,
    clustered_mean_test,
    compare_retention,
    paired_ttest,
    score_plans,
    stars,
)


def test_paired_ttest_matches_scipy() -> None:
    a = [1.0, 2 / 3, 1 / 3, 1.0, 0.0, 2 / 3]
    b = [1.0, 1.0, 1.0, 0.0, 1.0, 1.0]
    expected = stats.ttest_rel(a, b)
    result = paired_ttest(a, b)
    assert result.statistic == pytest.approx(expected.statistic)
    assert result.p_value == pytest.approx(expected.pvalue)
    assert result.mean_difference == pytest.approx(np.mean(np.subtract(a, b)))
    assert result.n == 6


def test_paired_ttest_undefined_cases_are_nan() -> None:
    assert math.isnan(paired_ttest([1.0], [0.0]).p_value)  # one pair
    assert math.isnan(paired_ttest([1.0, 1.0], [1.0, 1.0]).p_value)  # no variance
    with pytest.raises(ValueError, match="differ in length"):
        paired_ttest([1.0], [1.0, 0.0])


def test_clustered_test_reduces_to_the_paired_test_with_one_pair_per_task() -> None:
    d = [0.5, -1.0, 2.0, 1.5, 0.0]
    result = clustered_mean_test(d, ["a", "b", "c", "d", "e"])
    expected = stats.ttest_1samp(d, 0.0)
    assert result.statistic == pytest.approx(expected.statistic)
    assert result.p_value == pytest.approx(expected.pvalue)


def test_clustered_test_by_hand() -> None:
    # clusters a: (1, 3), b: (0,), c: (2, 2, 2); N=6, mean=10/6, G=3
    d = [1.0, 3.0, 0.0, 2.0, 2.0, 2.0]
    mean = 10 / 6
    sums = [(1 - mean) + (3 - mean), 0 - mean, 3 * (2 - mean)]
    se = math.sqrt(3 / 2 * sum(s * s for s in sums) / 36)
    result = clustered_mean_test(d, ["a", "a", "b", "c", "c", "c"])
    assert result.statistic == pytest.approx(mean / se)
    assert result.p_value == pytest.approx(2 * stats.t.sf(mean / se, 2))
    assert result.clusters == 3


def test_bootstrap_is_deterministic_and_seeded() -> None:
    rows = np.array([[1.0], [0.0], [1.0], [1.0], [0.0]])

    def mean(x: np.ndarray) -> np.ndarray:  # type: ignore[type-arg]
        return np.asarray(x.mean(axis=1))

    first = bootstrap_ci(rows, mean, resamples=300, seed=1)
    again = bootstrap_ci(rows, mean, resamples=300, seed=1)
    other = bootstrap_ci(rows, mean, resamples=300, seed=2)
    assert np.array_equal(first[0], again[0]) and np.array_equal(first[1], again[1])
    assert 0 <= first[0][0] <= 0.6 <= first[1][0] <= 1
    assert other is not None


@pytest.mark.parametrize(("p", "expected"), [(0.0004, "***"), (0.004, "**"), (0.04, "*"), (0.2, ""), (math.nan, "")])
def test_stars(p: float, expected: str) -> None:
    assert stars(p) == expected


def test_sr_change_test_is_the_per_task_paired_test() -> None:
    tasks = (BOOK, LAMP, HEAT, COOL)
    plans = {clean_id(t): reference(t) for t in tasks}
    # intrusion levels: BOOK 3/3, LAMP 0/3, HEAT 1/3, COOL 2/3
    solved = {BOOK: (1, 2, 3), LAMP: (), HEAT: (1,), COOL: (1, 2)}
    for task in tasks:
        for level in (1, 2, 3):
            plans[pattern_id(task, "intrusion", level)] = reference(task) if level in solved[task] else failing(task)
    scores = score_plans(plans, bootstrap=0)
    expected = stats.ttest_rel([1.0, 0.0, 1 / 3, 2 / 3], [1.0, 1.0, 1.0, 1.0])
    test = scores.sr_change_test["intrusion"]
    assert test.p_value == pytest.approx(expected.pvalue)
    assert test.statistic == pytest.approx(expected.statistic)
    assert scores.sr_change["intrusion"] == pytest.approx(0.5 - 1.0)
    # method vs method on per-task retention: a run that solves everything against this one
    perfect = score_plans({i: reference(i.split(":")[0]) for i in plans}, bootstrap=0)
    versus = compare_retention(scores, perfect)
    expected = stats.ttest_rel([1.0, 0.0, 1 / 3, 2 / 3], [1.0, 1.0, 1.0, 1.0])
    assert versus.p_value == pytest.approx(expected.pvalue)
    assert versus.mean_difference == pytest.approx(-0.5)
