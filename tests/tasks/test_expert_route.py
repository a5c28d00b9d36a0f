"""Reference plans whose plain conversion misses the expert's instance are routed past a landmark."""

from __future__ import annotations

import dataclasses

from talkdem.sim import run_plan
from talkdem.tasks import TaskSet, get_task, make_task, reference_plan


def _clean(task: object, plan: tuple[str, ...]) -> bool:
    trace = run_plan(task, plan)  # type: ignore[arg-type]
    return trace.success and all(s.ok for s in trace.steps)


def test_the_pan_in_the_cabinet_is_reached_through_a_landmark() -> None:
    stored = get_task("trial_T20190907_103940_774938")
    plain = tuple(reference_plan(stored))
    assert not _clean(stored, plain)  # "find a cabinet" reaches another cabinet than the expert opened
    made = make_task(stored, TaskSet.BENCHMARK, stored.scene_fixture_ids)
    assert made.reference_plan == stored.reference_plan
    assert len(made.reference_plan) == len(plain) + 1
    extra = [s for s in made.reference_plan if s.startswith("find")]
    assert len(extra) == len([s for s in plain if s.startswith("find")]) + 1
    assert _clean(made, made.reference_plan)


def test_a_plan_that_runs_clean_is_not_routed() -> None:
    stored = get_task("trial_T20190909_042716_008360")
    made = make_task(dataclasses.replace(stored), TaskSet.BENCHMARK, stored.scene_fixture_ids)
    assert made.reference_plan == tuple(reference_plan(stored))
