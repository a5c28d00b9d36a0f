"""Stopping with SIGTERM (`kill`, a scheduler, a sweep stopping its workers) leaves runs as Ctrl-C does: the
finished episodes saved, the header `incomplete`, exit 143; a stopped sweep stops its workers the same way.
Both are started as a background job is (`nohup ... &`: SIGINT ignored), where Ctrl-C's signal never arrives.
The planner is the scripted test model (tests/runs/run_scripted.py), slowed so there is time to stop it."""

from __future__ import annotations

import signal
import subprocess
import sys
import time
from pathlib import Path

from talkdem.runs import read_episodes, read_header

RUNS = Path(__file__).parent.parent / "runs"
SCRIPTED = [sys.executable, str(RUNS / "run_scripted.py"), "0.25"]
RUN = ["--backend", "scripted", "--model", "scripted-test-model", "--strategy", "vanilla", "--no-progress"]


def _background(command: list[str]) -> subprocess.Popen[str]:
    return subprocess.Popen(
        command,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_IGN),  # as `nohup ... &` starts it
    )


def _episodes(run_dir: Path) -> int:
    file = run_dir / "episodes.jsonl"
    return len(file.read_text().splitlines()) if file.is_file() else 0


def _wait_for(ready, process: subprocess.Popen[str], seconds: float = 120) -> None:  # type: ignore[no-untyped-def]
    deadline = time.monotonic() + seconds
    while not ready():
        assert process.poll() is None, process.communicate()
        assert time.monotonic() < deadline, "the job never got going"
        time.sleep(0.1)


def test_sigterm_saves_the_run_and_marks_it_incomplete(tmp_path: Path) -> None:
    out = tmp_path / "run"
    selection = ["--max-steps", "4", "--conditions", "clean,intrusion:1,intrusion:2", "--limit", "6"]
    process = _background([*SCRIPTED, "run", *RUN, *selection, "--out", str(out)])
    _wait_for(lambda: _episodes(out) >= 1, process)
    process.send_signal(signal.SIGTERM)
    _, err = process.communicate(timeout=60)
    assert process.returncode == 143, err
    assert err.strip().splitlines()[-1] == "talkdem run: terminated (finished episodes are saved; run again to resume)"
    header = read_header(out)
    stored = read_episodes(out)
    assert header.status == "incomplete" and 1 <= len(stored) < 18
    # and it resumes to the end, the saved episodes kept
    done = subprocess.run([*SCRIPTED, "run", *RUN, *selection, "--out", str(out)], capture_output=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert read_header(out).status == "complete" and len(read_episodes(out)) == 18
    assert read_episodes(out)[: len(stored)] == stored


SPEC = """\
out: OUT
models: [{model: scripted-test-model, backend: scripted, label: scripted}]
strategies: [vanilla]
conditions: [clean, intrusion:1, intrusion:2]
tasks: 6
planner: {max_steps: 4}
"""

SWEEP = """\
import functools, sys
sys.path.insert(0, PLANNER_TESTS)
from scripted_lm import ScriptedLM
from talkdem.llm.interface import registry
registry.BACKENDS.register("scripted", ScriptedLM)  # the spec's backend check; workers register their own
import talkdem.sweeps
talkdem.sweeps.run_sweep = functools.partial(talkdem.sweeps.run_sweep, talkdem=WORKER)
from talkdem.cli import main
sys.exit(main(["sweep", SPEC, "--workers", "2", "--threads", "1", "--no-progress"]))
"""


def test_a_stopped_sweep_stops_its_workers_and_each_shard_is_incomplete(tmp_path: Path) -> None:
    spec = tmp_path / "sweep.yaml"
    spec.write_text(SPEC.replace("OUT", str(tmp_path / "out")))
    launcher = tmp_path / "sweep_scripted.py"
    planner_tests = str(RUNS.parent / "planner")
    script = SWEEP.replace("WORKER", repr(SCRIPTED)).replace("SPEC", repr(str(spec)))
    launcher.write_text(script.replace("PLANNER_TESTS", repr(planner_tests)))
    process = _background([sys.executable, str(launcher)])
    shards = [tmp_path / "out" / ".sweep" / "scripted-vanilla" / f"shard-{i}-of-2" for i in (1, 2)]
    _wait_for(lambda: all(_episodes(s) >= 1 for s in shards), process)
    process.send_signal(signal.SIGTERM)
    _, err = process.communicate(timeout=90)
    assert process.returncode == 143, err
    assert "talkdem sweep: terminated" in err
    counts = [_episodes(s) for s in shards]
    assert all(read_header(s).status == "incomplete" for s in shards)
    time.sleep(1.5)
    assert [_episodes(s) for s in shards] == counts, "a worker kept running after the sweep stopped"
    assert all(1 <= c < 9 for c in counts)
