"""Every stored reference plan succeeds: no failed step, no hazard, every goal condition met."""

from __future__ import annotations

import subprocess
import sys

import pytest
from helpers import all_tasks

from talkdem.sim import EndReason, initial_state, run_plan
from talkdem.sim.goals import check_goals
from talkdem.tasks import Task

TASKS = all_tasks()


def test_there_are_400_tasks() -> None:
    assert len(TASKS) == 400


@pytest.mark.parametrize("task", TASKS, ids=lambda t: t.task_id)
def test_reference_plan_succeeds(task: Task) -> None:
    trace = run_plan(task, task.reference_plan)
    assert [(s.skill, s.message) for s in trace.steps if not s.ok] == []
    assert trace.hazards == ()
    assert trace.goal.success, trace.goal.conditions
    assert trace.end_reason is EndReason.DONE
    assert trace.analysis.missing_subgoals == ()


def test_no_goal_holds_at_the_start() -> None:
    for task in TASKS:
        assert not check_goals(task.task_type, task.pddl_params, initial_state(task)).success, task.task_id


def test_same_plan_same_state_hash() -> None:
    task = TASKS[0]
    first, second = run_plan(task, task.reference_plan), run_plan(task, task.reference_plan)
    assert first.state_hash == second.state_hash and len(first.state_hash) == 64
    assert first.state_hash != run_plan(task, ["done"]).state_hash


def test_episodes_do_not_leak_state_into_each_other() -> None:
    task = TASKS[0]
    before = initial_state(task).state_hash()
    run_plan(task, task.reference_plan)
    assert initial_state(task).state_hash() == before


def test_simulator_imports_no_heavy_libraries() -> None:
    code = (
        "import sys, talkdem.sim, talkdem.cli.simulate\n"
        "from talkdem.sim import run_plan\nfrom talkdem.tasks import load_tasks\n"
        "t = load_tasks('memory')[0]; run_plan(t, t.reference_plan)\n"
        "heavy = {'torch', 'transformers', 'datasets', 'evaluate', 'sentence_transformers'}\n"
        "print(sorted(heavy & set(sys.modules)))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"
