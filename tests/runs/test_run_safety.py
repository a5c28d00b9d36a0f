"""Run directories under hostile conditions: two writers, kills, edits, resumes with other settings.

Each test reproduces one way a run could be lost, duplicated or silently mixed, and checks the safe
behaviour: a refusal naming the problem, or a repair that loses nothing finished."""

from __future__ import annotations

import json
import subprocess
import sys
import time
from pathlib import Path

import pytest

from talkdem.runs import read_episodes, read_header
from talkdem.runs.external import record_plans
from talkdem.runs.oracle import write_oracle_run
from talkdem.runs.records import RecordError
from talkdem.runs.sampling import select_episodes
from talkdem.runs.store import EpisodeWriter, RunInUseError, run_lock, run_progress
from talkdem.schema import parse_conditions
from talkdem.tasks import get_task

SCRIPT = Path(__file__).parent / "run_scripted.py"
ARGS = ["run", "--backend", "scripted", "--model", "m", "--conditions", "clean,intrusion:1", "--limit", "2"]


def _scripted(out: Path, delay: float, *extra: str) -> subprocess.Popen[str]:
    command = [sys.executable, str(SCRIPT), str(delay), *ARGS, "--no-progress", "--out", str(out), *extra]
    return subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def _oracle_plans(conditions: str = "clean,intrusion:2", tasks: int = 2) -> dict[str, tuple[str, ...]]:
    return {e.id: get_task(e.task_id).reference_plan for e in select_episodes(parse_conditions(conditions), tasks)}


def test_a_second_writer_is_refused_and_nothing_is_duplicated(tmp_path: Path) -> None:
    run_dir = tmp_path / "run"
    first = _scripted(run_dir, 1.0)  # ~12 s in all: still writing when the second one starts
    deadline = time.time() + 120
    while time.time() < deadline and not (run_dir / "episodes.jsonl").exists():
        time.sleep(0.05)
    second = _scripted(run_dir, 0.0)
    _, error = second.communicate(timeout=120)
    assert first.poll() is None, "the first run must still hold the lock for this test to mean anything"
    assert second.returncode == 2
    assert "another talkdem process is writing this run" in error and "Traceback" not in error
    assert first.wait(timeout=300) == 0
    ids = [r.episode_id for r in read_episodes(run_dir)]
    assert len(ids) == 4 and len(set(ids)) == 4


def test_the_lock_is_exclusive_and_released(tmp_path: Path) -> None:
    # A second open file description conflicts even within one process, as another process would.
    with run_lock(tmp_path), pytest.raises(RunInUseError), run_lock(tmp_path):
        pass
    with run_lock(tmp_path):
        pass


@pytest.mark.parametrize(
    ("flag", "setting"),
    [
        (["--max-steps", "5"], "config.max_steps"),
        (["--scoring", "mean"], "config.scoring"),
        (["--feedback", "mask"], "config.mask_failed"),
        (["--feedback", "none"], "config.failure_message"),
    ],
)
def test_resuming_with_settings_that_change_results_is_refused(tmp_path: Path, flag: list[str], setting: str) -> None:
    run_dir = tmp_path / "run"
    assert _scripted(run_dir, 0.0).wait(timeout=300) == 0
    before = (run_dir / "episodes.jsonl").read_bytes()
    process = _scripted(run_dir, 0.0, *flag)
    _, error = process.communicate(timeout=120)
    assert process.returncode == 2 and "holds a different run" in error and setting in error
    assert (run_dir / "episodes.jsonl").read_bytes() == before


def test_episodes_without_a_header_are_not_adopted(tmp_path: Path) -> None:
    run_dir = tmp_path / "run"
    assert _scripted(run_dir, 0.0).wait(timeout=300) == 0
    (run_dir / "header.json").unlink()
    before = (run_dir / "episodes.jsonl").read_bytes()
    process = _scripted(run_dir, 0.0)
    _, error = process.communicate(timeout=120)
    assert process.returncode == 2 and "episodes without a header" in error
    assert (run_dir / "episodes.jsonl").read_bytes() == before


def test_a_folder_of_other_files_is_not_written_into(tmp_path: Path) -> None:
    (tmp_path / "notes.txt").write_text("mine")
    with pytest.raises(ValueError, match="other files, not a run directory"):
        record_plans(_oracle_plans(), tmp_path, "x")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["notes.txt"]


def test_a_killed_score_resumes_and_reports_progress(tmp_path: Path) -> None:
    plans = _oracle_plans()
    complete, killed = tmp_path / "complete", tmp_path / "killed"
    assert record_plans(plans, complete, "p") == 4
    assert record_plans(plans, killed, "p") == 4
    # As if killed after two episodes, in the middle of writing the third line.
    lines = (killed / "episodes.jsonl").read_text().splitlines(keepends=True)
    (killed / "episodes.jsonl").write_text("".join(lines[:2]) + lines[2][:50])
    with pytest.warns(UserWarning, match="truncated last record"):
        progress = run_progress(killed)
    assert (progress.done, progress.planned, progress.complete) == (2, 4, False)
    assert "INCOMPLETE" in str(progress)
    with pytest.warns(UserWarning, match="truncated last record"):
        record_plans(plans, killed, "p")
    strip = [{**r.to_json(), "timing": {}} for r in read_episodes(killed)]
    assert strip == [{**r.to_json(), "timing": {}} for r in read_episodes(complete)]
    assert run_progress(killed).complete


def test_resuming_a_score_with_other_plans_is_refused(tmp_path: Path) -> None:
    plans = _oracle_plans()
    record_plans(plans, tmp_path, "p")
    changed = {**plans, next(iter(plans)): ("find a spaceship", "done")}
    with pytest.raises(ValueError, match="plans_sha256"):
        record_plans(changed, tmp_path, "p")


def test_a_complete_last_line_without_newline_gets_one_before_appending(tmp_path: Path) -> None:
    plans = _oracle_plans()
    record_plans(plans, tmp_path, "p")
    path = tmp_path / "episodes.jsonl"
    records = read_episodes(tmp_path)
    path.write_text(path.read_text().rstrip("\n"))
    with EpisodeWriter(tmp_path) as writer:
        writer.write(records[0])
    lines = path.read_text().splitlines()
    assert len(lines) == 5 and json.loads(lines[3])["episode_id"] == records[3].episode_id


def _rewrite_record(run_dir: Path, index: int, **changes: object) -> None:
    path = run_dir / "episodes.jsonl"
    rows = [json.loads(line) for line in path.read_text().splitlines()]
    rows[index].update(changes)
    path.write_text("".join(json.dumps(r) + "\n" for r in rows))


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"plan": "find an apple"}, "a plan must be a list of skill strings"),
        ({"task_id": "trial_T00000000_000000_000000"}, "the id does not match task_id"),
        ({"level": 3}, "the id does not match"),
        ({"success": "yes"}, "field 'success' must be bool"),
        ({"level": True}, "field 'level' must be int"),
    ],
)
def test_hand_edited_records_are_refused(tmp_path: Path, change: dict[str, object], message: str) -> None:
    record_plans(_oracle_plans(), tmp_path, "p")
    _rewrite_record(tmp_path, 1, **change)
    with pytest.raises(RecordError, match=message):
        read_episodes(tmp_path)


def test_an_episode_stored_twice_is_refused(tmp_path: Path) -> None:
    record_plans(_oracle_plans(), tmp_path, "p")
    path = tmp_path / "episodes.jsonl"
    first = path.read_text().splitlines()[0]
    path.write_text(path.read_text() + first + "\n")
    with pytest.raises(ValueError, match=r"line 5: episode .* is stored twice"):
        read_episodes(tmp_path)


@pytest.mark.parametrize(
    ("header", "message"),
    [
        (
            {"model": "m", "planner": "p", "strategy": "s", "prompt_version": "", "dataset_hash": ""},
            "'model' must be dict",
        ),
        (
            {"model": {}, "planner": 3, "strategy": "s", "prompt_version": "", "dataset_hash": ""},
            "'planner' must be str",
        ),
        ([1, 2], "expected a JSON object"),
    ],
)
def test_malformed_headers_are_refused(tmp_path: Path, header: object, message: str) -> None:
    (tmp_path / "header.json").write_text(json.dumps(header))
    with pytest.raises(RecordError, match=message):
        read_header(tmp_path)


def test_a_header_that_is_a_folder(tmp_path: Path) -> None:
    (tmp_path / "header.json").mkdir()
    with pytest.raises(FileNotFoundError, match="not a run directory"):
        read_header(tmp_path)


def test_the_oracle_replaces_only_its_own_run(tmp_path: Path) -> None:
    first = select_episodes(parse_conditions("clean"), 1)
    second = select_episodes(parse_conditions("clean"), 2)
    assert write_oracle_run(first, tmp_path / "oracle") == 1
    assert write_oracle_run(second, tmp_path / "oracle") == 2
    assert len(read_episodes(tmp_path / "oracle")) == 2
    other = tmp_path / "other"
    record_plans(_oracle_plans("clean", 1), other, "my-planner")
    before = (other / "episodes.jsonl").read_bytes()
    with pytest.raises(ValueError, match="holds a different run"):
        write_oracle_run(second, other)
    assert (other / "episodes.jsonl").read_bytes() == before


def test_headers_name_no_machine_paths(tmp_path: Path) -> None:
    plan_file = tmp_path / "deep" / "plans.jsonl"
    plan_file.parent.mkdir()
    plan_file.write_text(
        "".join(json.dumps({"episode_id": k, "plan": list(v)}) + "\n" for k, v in _oracle_plans().items())
    )
    from talkdem.runs.external import record_plan_file

    record_plan_file(plan_file, tmp_path / "run", "p")
    assert str(tmp_path) not in (tmp_path / "run" / "header.json").read_text()
    assert read_header(tmp_path / "run").config["plans"] == "plans.jsonl"


def test_a_run_through_the_result_cache_gives_the_same_records(tmp_path: Path) -> None:
    cache = tmp_path / "scores.sqlite"
    plain, first, second = tmp_path / "plain", tmp_path / "first", tmp_path / "second"
    assert _scripted(plain, 0.0).wait(timeout=300) == 0
    assert _scripted(first, 0.0, "--cache", str(cache)).wait(timeout=300) == 0
    assert cache.stat().st_size > 0
    assert _scripted(second, 0.0, "--cache", str(cache)).wait(timeout=300) == 0

    def plans(run_dir: Path) -> list[tuple[str, tuple[str, ...]]]:
        return [(r.episode_id, r.plan) for r in read_episodes(run_dir)]

    assert plans(first) == plans(second) == plans(plain)


def test_strategy_options_are_recorded_and_a_resume_with_others_is_refused(tmp_path: Path) -> None:
    run_dir = tmp_path / "run"
    assert _scripted(run_dir, 0.0, "--strategy", "tocc").wait(timeout=300) == 0
    header = read_header(run_dir)
    assert header.config["strategy_args"] == {"max_new_tokens": 128, "stop": [".", "?", "!"], "chat": True}
    assert header.config["feedback"] == "message" and header.config["failure_message"] is True
    episode = read_episodes(run_dir)[0]
    assert episode.notes["rewrite_status"] == "ok" and episode.instruction_shown == episode.notes["rewrite"]
    process = _scripted(run_dir, 0.0, "--strategy", "tocc", "--strategy-arg", "max_new_tokens=64")
    _, error = process.communicate(timeout=120)
    assert process.returncode == 2 and "config.strategy_args" in error and "prompt_version" in error


def test_an_option_of_another_strategy_is_one_clear_error(tmp_path: Path) -> None:
    process = _scripted(tmp_path / "run", 0.0, "--strategy-arg", "order=best_first")
    _, error = process.communicate(timeout=120)
    assert process.returncode == 2 and "Traceback" not in error
    assert "strategy arg 'order': the vanilla strategy has no such option (its options: none); care has it" in error
    assert not (tmp_path / "run").exists()
