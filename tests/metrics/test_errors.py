"""The error classifier on constructed plans of each type, run through the real simulator on real tasks."""

from __future__ import annotations

import pytest
from metrics_helpers import BOOK, HEAT, LAMP, clean_id, pattern_id, reference

from talkdem.metrics import ErrorType, classify_error, score_plans
from talkdem.sim import run_plan
from talkdem.tasks import get_task


def heat_reference() -> list[str]:
    return reference(HEAT)  # find/pick up the potato, heat it in the microwave, put it on a counter top


CASES = {
    ErrorType.REFERENT: (HEAT, [s.replace("potato", "apple") for s in heat_reference()]),
    ErrorType.STATE: (
        HEAT,
        ["find a potato", "pick up the potato", "find a counter top", "put down the potato", "done"],
    ),
    ErrorType.LOCATION: (HEAT, [*heat_reference()[:-3], "find a dining table", "put down the potato", "done"]),
    ErrorType.SUBGOAL: (LAMP, ["find a box", "pick up the box", "done"]),
    ErrorType.ORGANIZATION: (
        LAMP,
        ["find a desk lamp", "turn on the desk lamp", "find a box", "pick up the box", "done"],
    ),
    ErrorType.EXECUTION: (HEAT, heat_reference()[1:]),  # no `find a potato`: the pick up fails
}


@pytest.mark.parametrize("expected", list(CASES))
def test_each_constructed_failure_gets_its_type(expected: ErrorType) -> None:
    task_id, plan = CASES[expected]
    task = get_task(task_id)
    trace = run_plan(task, plan)
    assert not trace.success
    found = classify_error(task, trace)
    assert found is not None and found.type is expected, found
    assert found.reason


def test_successful_episodes_are_not_classified() -> None:
    task = get_task(BOOK)
    assert classify_error(task, run_plan(task, reference(BOOK))) is None


def test_scores_classify_only_failures_that_succeeded_under_clean() -> None:
    plans = {clean_id(HEAT): heat_reference(), clean_id(LAMP): CASES[ErrorType.SUBGOAL][1]}
    for level, kind in enumerate((ErrorType.REFERENT, ErrorType.STATE, ErrorType.EXECUTION), start=1):
        plans[pattern_id(HEAT, "object_substitution", level)] = CASES[kind][1]
    plans[pattern_id(LAMP, "object_substitution", 1)] = CASES[ErrorType.ORGANIZATION][1]  # clean failed too
    scores = score_plans(plans, bootstrap=0)
    counts = scores.error_counts("object_substitution")
    assert counts[ErrorType.REFERENT] == counts[ErrorType.STATE] == counts[ErrorType.EXECUTION] == 1
    assert counts[ErrorType.ORGANIZATION] == 0
    assert sum(scores.error_counts().values()) == 3
