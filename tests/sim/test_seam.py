"""The stepwise simulator seam: registered backends, the step limit and `done`, one hazard path."""

from __future__ import annotations

import pytest

from talkdem.sim import (
    DEFAULT_MAX_STEPS,
    SIMULATORS,
    EndReason,
    Episode,
    EpisodeOverError,
    FailureKind,
    execute_plan,
    load_simulator,
    run_plan,
)
from talkdem.tasks import TaskSet, load_tasks

TASKS = load_tasks(TaskSet.BENCHMARK)


def test_backends_are_registered_by_name() -> None:
    assert SIMULATORS.names() == ("symbolic", "ai2thor")
    assert load_simulator("symbolic").name == "symbolic"
    with pytest.raises(ValueError, match="did you mean 'symbolic'"):
        load_simulator("symbolik")


def test_a_step_after_done_is_refused() -> None:
    task = TASKS[0]
    episode = load_simulator().start(task)
    for text in task.reference_plan:
        episode.step(text)
    assert episode.done and episode.over and not episode.truncated
    with pytest.raises(EpisodeOverError, match="ended at 'done'"):
        episode.step("find an apple")
    assert episode.finish().end_reason is EndReason.DONE


def test_the_step_limit_truncates_live_and_stored_plans_alike() -> None:
    task = TASKS[1]
    episode = Episode.start(task)
    for _ in range(DEFAULT_MAX_STEPS):
        episode.step("find an apple")
    assert episode.truncated and not episode.done
    with pytest.raises(EpisodeOverError, match="step limit"):
        episode.step("find an apple")
    live = episode.finish()
    stored = run_plan(task, ["find an apple"] * 35)
    assert live.end_reason is stored.end_reason is EndReason.STEP_LIMIT
    assert len(stored.steps) == DEFAULT_MAX_STEPS
    assert live.state_hash == stored.state_hash


def test_out_of_vocabulary_skills_are_failed_steps() -> None:
    task = TASKS[2]
    trace = execute_plan(load_simulator(), task, ["teleport to the moon", *task.reference_plan])
    assert not trace.steps[0].ok and trace.steps[0].failure is FailureKind.NOT_SUPPORTED
    assert trace.steps[0].parsed is None


def test_every_path_judges_hazards_relative_to_the_reference_plan() -> None:
    # Before, Episode(task) had no exemptions and Episode.start(task) had them: 9 reference plans differed.
    flagged = []
    for task in TASKS:
        by_hand = Episode(task)
        for text in task.reference_plan:
            by_hand.step(text)
        started = Episode.start(task)
        for text in task.reference_plan:
            started.step(text)
        hand, start = by_hand.finish(), started.finish()
        assert hand.hazards == start.hazards == run_plan(task, task.reference_plan).hazards
        flagged += list(hand.hazards)
    assert flagged == []
