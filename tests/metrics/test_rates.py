"""Success rate, retention and their averages on small hand-computed cases, executed on real tasks."""

from __future__ import annotations

import math

import numpy as np
import pytest
from metrics_helpers import BOOK, COOL, HEAT, LAMP, clean_id, failing, pattern_id, reference

from talkdem.metrics import CONDITIONS, MEASURES, measures, score_plans
from talkdem.schema import PATTERN_CONFIGS


@pytest.fixture(scope="module")
def scores():  # type: ignore[no-untyped-def]
    # Clean: BOOK, LAMP, HEAT solved, COOL failed -> clean SR 3/4.
    # intrusion:1: BOOK ok, LAMP failed, HEAT ok, COOL ok -> SR 3/4; retention 2/3 (COOL is not clean-solved).
    # intrusion:2: all four ok -> SR 1, retention 3/3. intrusion:3: BOOK only ok -> SR 1/4, retention 1/3.
    # topic_drift:1: BOOK and COOL only, both failed -> SR 0, retention 0/1.
    plans = {
        clean_id(BOOK): reference(BOOK),
        clean_id(LAMP): reference(LAMP),
        clean_id(HEAT): reference(HEAT),
        clean_id(COOL): failing(COOL),
        pattern_id(BOOK, "intrusion", 1): reference(BOOK),
        pattern_id(LAMP, "intrusion", 1): failing(LAMP),
        pattern_id(HEAT, "intrusion", 1): reference(HEAT),
        pattern_id(COOL, "intrusion", 1): reference(COOL),
        **{pattern_id(t, "intrusion", 2): reference(t) for t in (BOOK, LAMP, HEAT, COOL)},
        pattern_id(BOOK, "intrusion", 3): reference(BOOK),
        **{pattern_id(t, "intrusion", 3): failing(t) for t in (LAMP, HEAT, COOL)},
        pattern_id(BOOK, "topic_drift", 1): failing(BOOK),
        pattern_id(COOL, "topic_drift", 1): failing(COOL),
    }
    return score_plans(plans, bootstrap=200)


def test_success_rate_per_condition(scores) -> None:  # type: ignore[no-untyped-def]
    sr = scores.success_rate
    assert sr["clean"] == 0.75
    assert (sr["intrusion:1"], sr["intrusion:2"], sr["intrusion:3"]) == (0.75, 1.0, 0.25)
    assert sr["intrusion"] == pytest.approx((0.75 + 1.0 + 0.25) / 3)
    assert sr["topic_drift:1"] == 0.0 and sr["topic_drift"] == 0.0
    assert math.isnan(sr["empty_speech:1"]) and math.isnan(sr["empty_speech"])
    assert sr["average"] == pytest.approx((0.75 + 1.0 + 0.25 + 0.0) / 4)  # mean over evaluated conditions
    assert scores.sr_change["intrusion"] == pytest.approx(2 / 3 - 0.75)
    assert scores.n_episodes == 18 and scores.n_tasks == 4


def test_retention(scores) -> None:  # type: ignore[no-untyped-def]
    r = scores.retention
    assert scores.clean_successes == 3
    assert (r["intrusion:1"], r["intrusion:2"], r["intrusion:3"]) == pytest.approx((2 / 3, 1.0, 1 / 3))
    assert r["intrusion"] == pytest.approx(2 / 3)
    assert r["topic_drift:1"] == 0.0
    assert math.isnan(r["object_substitution:2"])
    assert r["average"] == pytest.approx((2 / 3 + 1 + 1 / 3 + 0) / 4)
    # per task (clean-solved): BOOK solved 3 of its 4 pattern episodes; LAMP 1 of 3; HEAT 2 of 3
    assert scores.task_retention["all"] == pytest.approx({BOOK: 3 / 4, LAMP: 1 / 3, HEAT: 2 / 3})
    assert scores.task_retention["intrusion"] == pytest.approx({BOOK: 1.0, LAMP: 1 / 3, HEAT: 2 / 3})


def test_bootstrap_intervals_bracket_the_estimates(scores) -> None:  # type: ignore[no-untyped-def]
    for key in ("sr/clean", "sr/intrusion", "retention/intrusion:1", "retention/average"):
        low, high = scores.intervals[key]
        estimate = scores.success_rate.get(key[3:]) if key.startswith("sr/") else scores.retention[key[10:]]
        assert low <= estimate <= high


def test_flat_dict_has_every_condition(scores) -> None:  # type: ignore[no-untyped-def]
    flat = scores.flat()
    assert flat["success_rate/clean"] == 0.75
    assert flat["success_rate/empty_speech:1"] is None  # NaN never leaks into the flat output
    assert flat["retention/intrusion:3"] == pytest.approx(1 / 3)
    assert all(f"sr_change/{p}" in flat for p in PATTERN_CONFIGS)


def test_measures_on_a_matrix_by_hand() -> None:
    # 3 tasks; clean = 1,1,0; intrusion:1 = 1,0,1; everything else missing.
    matrix = np.full((3, len(CONDITIONS)), np.nan)
    column = CONDITIONS.index(next(c for c in CONDITIONS if str(c) == "intrusion:1"))
    matrix[:, 0] = [1, 1, 0]
    matrix[:, column] = [1, 0, 1]
    values = dict(zip(MEASURES, measures(matrix), strict=True))
    assert values["sr/clean"] == pytest.approx(2 / 3)
    assert values["sr/intrusion:1"] == pytest.approx(2 / 3)
    assert values["retention/intrusion:1"] == pytest.approx(1 / 2)
    assert values["retention/average"] == pytest.approx(1 / 2)


def test_reference_plans_score_perfectly_on_a_slice() -> None:
    from talkdem.instructions import load_instructions

    chosen = [i for i in load_instructions() if str(i.condition) in ("clean", "object_substitution:2")][:200]
    plans = {i.id: reference(i.task_id) for i in chosen}
    scores = score_plans(plans, retention=False, bootstrap=0)
    assert scores.success_rate["clean"] == 1.0
    assert scores.retention is None
