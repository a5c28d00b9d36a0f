"""The parity suite: stored perturbed plans replay to the stored verdicts; `talkdem parity` on a sample."""

from __future__ import annotations

import pytest

from talkdem.cli import main
from talkdem.sim import SymbolicExecutor
from talkdem.sim.parity import build_cases, load_cases, parity_file, replay
from talkdem.sim.perturb import PerturbationKind, perturb
from talkdem.tasks import TaskSet, load_tasks

TASKS = load_tasks(TaskSet.BENCHMARK)
CASES = load_cases(parity_file())


def test_every_task_has_cases_of_every_kind_that_applies() -> None:
    by_task: dict[str, set[str]] = {}
    for case in CASES:
        by_task.setdefault(case.task_id, set()).add(case.kind)
    assert set(by_task) == {t.task_id for t in TASKS}
    assert all({"reorder", "drop", "extra"} <= kinds for kinds in by_task.values())
    movable = {t.task_id for t in TASKS if t.task_type == "pick_and_place_with_movable_recep"}
    assert {c.task_id for c in CASES if c.kind == PerturbationKind.CONTAINER_FIRST} <= movable


def test_stored_cases_are_regenerated_from_the_seed() -> None:
    for task in TASKS[::37]:
        stored = [(c.case_id, c.plan) for c in CASES if c.task_id == task.task_id]
        assert [(p.case_id, p.plan) for p in perturb(task, task.reference_plan)] == stored


def test_a_sample_replays_to_the_stored_verdicts() -> None:
    sample = [c for c in CASES if c.task_id in {t.task_id for t in TASKS[::25]}]
    report = replay(sample, {t.task_id: t for t in TASKS}, SymbolicExecutor())
    assert report.cases == len(sample) > 0
    assert report.disagreements == []
    assert report.rules["goal"].total == len(sample)


def test_a_changed_rule_shows_up_as_disagreement() -> None:
    # Flip one stored verdict: the replay must name that case and count it against its rule and task type.
    case = next(c for c in CASES if c.kind == "container_first")
    flipped = type(case)(**{**case.__dict__, "success": not case.success})
    report = replay([flipped], {t.task_id: t for t in TASKS}, SymbolicExecutor())
    assert report.disagreements == [case.case_id]
    assert report.rules["goal"].agree == 0
    assert report.task_types[case.task_type].agree == 0


def test_stored_verdicts_match_a_fresh_build_for_a_sample() -> None:
    fresh = build_cases(TASKS[:5], SymbolicExecutor())
    stored = [c for c in CASES if c.task_id in {t.task_id for t in TASKS[:5]}]
    assert fresh == stored


def test_cli_sample(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["parity", "--limit", "40"]) == 0
    out = capsys.readouterr().out
    assert "40 cases, whole-case agreement 1.000" in out
    assert "| step:find |" in out and "| goal | 40 | 40 | 1.000 |" in out


@pytest.mark.parametrize("argv", [["parity", "--limit", "0"], ["parity", "--backend", "unity"]])
def test_cli_bad_arguments_exit_nonzero(argv: list[str]) -> None:
    with pytest.raises(SystemExit) as exc:
        main(argv)
    assert exc.value.code == 2


def test_cli_ai2thor_without_a_build_is_one_clear_line(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["parity", "--backend", "ai2thor", "--limit", "1"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("talkdem parity: error:") and "ai2thor" in err[0].lower()
