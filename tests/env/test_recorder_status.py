"""An agent's recording ends with the status every run writer sets (`finish_status`): `running` while it is
open, `complete` once every planned episode is on disk, `incomplete` when some are missing or the recording
ended in an exception; a resumed recording that fills the gap becomes `complete`."""

from __future__ import annotations

from pathlib import Path

import pytest

from talkdem.env import EpisodeRecorder, select
from talkdem.instructions import Instruction
from talkdem.report.runs import score_runs
from talkdem.runs import read_header
from talkdem.sim import run_plan
from talkdem.tasks import get_task


@pytest.fixture(scope="module")
def episodes() -> list[Instruction]:
    return select("clean", limit=3)


def _record(recorder: EpisodeRecorder, instruction: Instruction) -> None:
    task = get_task(instruction.task_id)
    plan = list(task.reference_plan)
    recorder.record(instruction, plan, run_plan(task, plan))


def test_every_planned_episode_recorded_is_complete(tmp_path: Path, episodes: list[Instruction]) -> None:
    run_dir = tmp_path / "run"
    with EpisodeRecorder(run_dir, "agent", "1", planned=episodes) as recorder:
        for instruction in episodes:
            _record(recorder, instruction)
            assert read_header(run_dir).status == "running", "running while the recorder is open"
    assert read_header(run_dir).status == "complete"
    (run,) = score_runs([run_dir], bootstrap=0)
    assert run.coverage.complete


def test_a_recording_short_of_its_plan_is_incomplete_until_resumed(tmp_path: Path, episodes: list[Instruction]) -> None:
    run_dir = tmp_path / "run"
    recorder = EpisodeRecorder(run_dir, "agent", "1", planned=episodes)
    _record(recorder, episodes[0])
    recorder.close()
    recorder.close()  # a second close changes nothing
    assert read_header(run_dir).status == "incomplete"
    with EpisodeRecorder(run_dir, "agent", "1", planned=episodes) as again:
        assert again.recorded == {episodes[0].id}
        assert read_header(run_dir).status == "running"
        for instruction in episodes[1:]:
            _record(again, instruction)
    assert read_header(run_dir).status == "complete"


def test_a_recording_ended_by_an_exception_is_incomplete(tmp_path: Path, episodes: list[Instruction]) -> None:
    run_dir = tmp_path / "run"
    with pytest.raises(KeyboardInterrupt), EpisodeRecorder(run_dir, "agent", "1", planned=episodes[:1]) as rec:
        _record(rec, episodes[0])
        raise KeyboardInterrupt  # as `talkdem run` does: a run stopped by an error is not called complete
    assert read_header(run_dir).status == "incomplete"
    with EpisodeRecorder(run_dir, "agent", "1", planned=episodes[:1]):
        pass  # nothing left to record: closing normally finds every planned episode on disk
    assert read_header(run_dir).status == "complete"


def test_a_recording_without_a_plan_is_complete_with_what_it_recorded(
    tmp_path: Path, episodes: list[Instruction]
) -> None:
    run_dir = tmp_path / "run"
    with EpisodeRecorder(run_dir, "agent", "1") as recorder:
        _record(recorder, episodes[0])
    header = read_header(run_dir)
    assert header.status == "complete" and "planned_episodes" not in header.config
