"""Property tests: random skill sequences on real tasks never raise while the episode is open, keep the state
consistent, and a step after the episode ended (`done`, the step limit) is refused."""

from __future__ import annotations

import pytest
from helpers import all_tasks
from hypothesis import given, settings
from hypothesis import strategies as st

from talkdem.sim import EndReason, Episode, EpisodeOverError, SimState
from talkdem.skills import vocabulary

TASKS = all_tasks()[::20]  # 20 tasks across every task type and both sets
SKILLS = [s.text for s in vocabulary()] + ["", "fly", "Find An Apple.", "put down the moon"]


def _check_invariants(state: SimState) -> None:
    held = state.held
    assert held is None or held in state.present
    assert held is None or not state.parent_receptacles(held), "a held object is in no receptacle"
    for receptacle, inside in state.contents.items():
        for item in inside:
            assert state.parent[item] == receptacle
    for item, receptacle in state.parent.items():
        assert item in state.contents[receptacle], "containment is mirrored"
    for obj in state.present:
        chain = state.parent_receptacles(obj)
        assert len(chain) == len(set(chain)), "no containment cycle"
        for receptacle in chain:
            assert obj in state.receptacle_object_ids(receptacle), "containment is transitive"
        if held is not None:
            assert held not in state.receptacle_object_ids(obj)


@settings(max_examples=150, deadline=None)
@given(task_index=st.integers(0, len(TASKS) - 1), plan=st.lists(st.sampled_from(SKILLS), max_size=25))
def test_random_plans_keep_invariants(task_index: int, plan: list[str]) -> None:
    task = TASKS[task_index]
    episode = Episode(task)
    _check_invariants(episode.state)
    for text in plan:
        if episode.over:
            with pytest.raises(EpisodeOverError):
                episode.step(text)
            break
        record = episode.step(text)
        assert record.ok or record.message
        _check_invariants(episode.state)
    trace = episode.finish(EndReason.PLAN_EXHAUSTED)
    assert trace.goal.total >= 1


@settings(max_examples=60, deadline=None)
@given(task_index=st.integers(0, len(TASKS) - 1), plan=st.lists(st.sampled_from(SKILLS), max_size=12))
def test_reference_steps_mixed_with_noise_never_raise(task_index: int, plan: list[str]) -> None:
    task = TASKS[task_index]
    episode = Episode(task)
    for text in [*task.reference_plan[:4], *plan]:
        if episode.over:  # `done` ends it: a further step is refused, not executed
            break
        episode.step(text)
        _check_invariants(episode.state)
