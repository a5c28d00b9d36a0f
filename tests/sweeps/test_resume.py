"""The sweep's own logic on the scripted test model (workers start tests/runs/run_scripted.py): a run already
on disk is split and its finished episodes seed the shards (never run again), the merged run equals one serial
run, a finished sweep runs nothing again, and a finished run with other settings is refused, not skipped."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from talkdem.cli import main
from talkdem.runs import read_header
from talkdem.sweeps import load_sweep, run_sweep

SCRIPTED = [sys.executable, str(Path(__file__).parent.parent / "runs" / "run_scripted.py"), "0"]
SPEC = """\
out: OUT
models: [{model: scripted-test-model, backend: scripted, label: scripted}]
strategies: [vanilla]
conditions: [clean, intrusion:1]
tasks: 2
planner: {max_steps: STEPS}
"""
RUN = ["--backend", "scripted", "--model", "scripted-test-model", "--strategy", "vanilla", "--no-progress"]


def _spec(tmp_path: Path, steps: int = 4) -> Path:
    path = tmp_path / f"sweep-{steps}.yaml"
    path.write_text(SPEC.replace("OUT", str(tmp_path / "out")).replace("STEPS", str(steps)))
    return path


def _serial(out: Path, conditions: str) -> None:
    selection = ["--max-steps", "4", "--conditions", conditions, "--limit", "2"]
    command = [*SCRIPTED, "run", *RUN, *selection, "--out", str(out)]
    done = subprocess.run(command, capture_output=True, text=True, timeout=300, check=False)
    assert done.returncode == 0, done.stderr


def _records(run_dir: Path) -> list[dict[str, object]]:
    lines = (run_dir / "episodes.jsonl").read_text().splitlines()
    return [{k: v for k, v in json.loads(line).items() if k != "timing"} for line in lines]


def test_a_run_on_disk_is_split_resumed_merged_and_then_left_alone(tmp_path: Path) -> None:
    spec = load_sweep(_spec(tmp_path))
    (run,) = spec.runs
    _serial(run.run_dir, "clean")  # 2 of the 4 episodes already done, by a serial run
    started = _records(run.run_dir)
    result = run_sweep(spec, workers=2, threads=1, progress=False, talkdem=SCRIPTED)
    assert result.failures == () and result.complete == (str(run.run_dir),)
    assert (result.resumed, result.episodes) == (2, 4)
    serial = tmp_path / "serial"
    _serial(serial, "clean,intrusion:1")
    assert _records(run.run_dir) == _records(serial)
    assert all(record in _records(run.run_dir) for record in started)
    assert read_header(run.run_dir).config["merged_from"] == ["1/2", "2/2"]
    assert not (spec.out / ".sweep").exists(), "the shard folders are removed once merged"

    # Finished: nothing runs again (a worker that fails at once would be a failure here).
    again = run_sweep(spec, workers=2, threads=1, progress=False, talkdem=[sys.executable, "-c", "raise SystemExit(3)"])
    assert again.failures == () and (again.resumed, again.episodes) == (4, 4)


def test_a_sweep_stopped_before_its_last_shards_started_resumes(tmp_path: Path) -> None:
    """One worker, two shards: the second shard's folder is made only when its job starts, so a sweep stopped
    during the first leaves one shard folder; the resume runs the missing shard and merges both."""
    spec = load_sweep(_spec(tmp_path))
    (run,) = spec.runs
    first = spec.out / ".sweep" / run.name / "shard-1-of-2"
    _serial_shard(first, "1/2")  # what the stopped sweep had finished
    started = _records(first)
    result = run_sweep(spec, workers=1, shards=2, threads=1, progress=False, talkdem=SCRIPTED)
    assert result.failures == () and result.complete == (str(run.run_dir),)
    assert (result.resumed, result.episodes) == (len(started), 4)
    serial = tmp_path / "serial"
    _serial(serial, "clean,intrusion:1")
    assert _records(run.run_dir) == _records(serial)


def test_shard_folders_of_different_splits_are_refused(tmp_path: Path) -> None:
    spec = load_sweep(_spec(tmp_path))
    (run,) = spec.runs
    for folder in ("shard-1-of-2", "shard-2-of-3"):
        (spec.out / ".sweep" / run.name / folder).mkdir(parents=True)
    with pytest.raises(ValueError, match=r"holds shard folders of different splits"):
        run_sweep(spec, workers=1, threads=1, progress=False, talkdem=SCRIPTED)


def _serial_shard(out: Path, shard: str) -> None:
    selection = ["--max-steps", "4", "--conditions", "clean,intrusion:1", "--limit", "2", "--shard", shard]
    command = [*SCRIPTED, "run", *RUN, *selection, "--out", str(out)]
    done = subprocess.run(command, capture_output=True, text=True, timeout=300, check=False)
    assert done.returncode == 0, done.stderr


def test_a_finished_run_with_other_settings_is_refused(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    spec = load_sweep(_spec(tmp_path))
    assert run_sweep(spec, workers=1, threads=1, progress=False, talkdem=SCRIPTED).failures == ()
    assert main(["sweep", str(_spec(tmp_path, steps=5)), "--no-progress"]) == 2
    error = capsys.readouterr().err
    assert "holds a different run (config.max_steps: 4 there, 5 now)" in error and len(error.splitlines()) == 1


def test_a_failed_job_is_reported_and_resumes(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    spec = load_sweep(_spec(tmp_path))
    failing = [sys.executable, "-c", "import sys; print('no model here'); sys.exit(2)"]
    result = run_sweep(spec, workers=2, threads=1, progress=False, talkdem=failing)
    assert result.complete == () and len(result.failures) == 2
    assert all("no model here (exit 2; output in" in failure for failure in result.failures)
    resumed = run_sweep(spec, workers=2, threads=1, progress=False, talkdem=SCRIPTED)
    assert resumed.failures == () and resumed.episodes == 4


def test_packed_runs_are_resumed_and_left_alone_by_a_sweep(tmp_path: Path) -> None:
    from talkdem.runs import EPISODES_FILE, PACKED_EPISODES_FILE
    from talkdem.runs.pack import pack_run

    spec = load_sweep(_spec(tmp_path))
    (run,) = spec.runs
    _serial(run.run_dir, "clean")  # 2 of the 4 episodes, then packed as committed runs are
    started = _records(run.run_dir)
    assert pack_run(run.run_dir, partial=True).changed
    result = run_sweep(spec, workers=2, threads=1, progress=False, talkdem=SCRIPTED)
    assert result.failures == () and (result.resumed, result.episodes) == (2, 4)
    assert not (run.run_dir / PACKED_EPISODES_FILE).exists()
    assert all(record in _records(run.run_dir) for record in started)

    assert pack_run(run.run_dir).changed  # finished and packed: settled, nothing runs, it stays packed
    packed = (run.run_dir / PACKED_EPISODES_FILE).read_bytes()
    again = run_sweep(spec, workers=2, threads=1, progress=False, talkdem=[sys.executable, "-c", "raise SystemExit(3)"])
    assert again.failures == () and (again.resumed, again.episodes) == (4, 4)
    assert (run.run_dir / PACKED_EPISODES_FILE).read_bytes() == packed and not (run.run_dir / EPISODES_FILE).exists()


def test_a_ray_job_that_unpacked_its_run_replaces_the_packed_file(tmp_path: Path) -> None:
    from talkdem.runs import EPISODES_FILE, HEADER_FILE, PACKED_EPISODES_FILE
    from talkdem.sweeps.ray_cluster import _seed, _write_back

    target = tmp_path / "run"
    target.mkdir()
    (target / HEADER_FILE).write_text("{}")
    (target / PACKED_EPISODES_FILE).write_bytes(b"packed")
    assert set(_seed(target)) == {HEADER_FILE, PACKED_EPISODES_FILE}, "a packed run seeds its job"
    _write_back(target, {HEADER_FILE: b"{}", PACKED_EPISODES_FILE: b"packed"})  # nothing ran
    assert (target / PACKED_EPISODES_FILE).read_bytes() == b"packed" and not (target / EPISODES_FILE).exists()
    _write_back(target, {HEADER_FILE: b"{ }", EPISODES_FILE: b"plain\n"})  # the job unpacked it to append
    assert sorted(p.name for p in target.iterdir()) == [EPISODES_FILE, HEADER_FILE]
    assert (target / EPISODES_FILE).read_bytes() == b"plain\n" and (target / HEADER_FILE).read_bytes() == b"{ }"
