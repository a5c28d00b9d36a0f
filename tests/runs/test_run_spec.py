"""The run spec: every input file hashed into the header, a resume refused when one changed or the code
revision moved, a `status` kept up to date, every header field validated on read.

Inputs are edited in copies of the dataset (`TALKDEM_DATA_DIR`), never in `data/`."""

from __future__ import annotations

import hashlib
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from talkdem.paths import repo_root
from talkdem.planner.saycan import SayCanConfig
from talkdem.planner.strategies import load_strategy
from talkdem.runs import read_episodes, read_header
from talkdem.runs.records import RecordError, RunHeader
from talkdem.runs.spec import OUTCOME_KEYS, RunSpec, input_hashes, planner_settings
from talkdem.runs.store import run_progress

SCRIPT = Path(__file__).parent / "run_scripted.py"
ARGS = ["run", "--backend", "scripted", "--model", "m", "--conditions", "clean,intrusion:1", "--limit", "2"]
HEX = set("0123456789abcdef")


def _data_copy(tmp_path: Path) -> Path:
    copy = tmp_path / "data-copy"
    shutil.copytree(repo_root() / "data", copy, ignore=shutil.ignore_patterns("parity"))
    return copy


def _scripted(out: Path, data: Path | None, *extra: str, delay: float = 0.0) -> subprocess.Popen[str]:
    env = {**os.environ, **({"TALKDEM_DATA_DIR": str(data)} if data else {})}
    command = [sys.executable, str(SCRIPT), str(delay), *ARGS, "--no-progress", "--out", str(out), *extra]
    # SIGINT as a foreground process has it (where Ctrl-C reaches it): a test run started in the background
    # inherits it ignored, and the Ctrl-C test below would then see a run that never got the signal.
    return subprocess.Popen(
        command,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=env,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )


def _finish(process: subprocess.Popen[str]) -> tuple[int, str, str]:
    out, err = process.communicate(timeout=300)
    return process.returncode, out, err


def _sha(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def _half_run(tmp_path: Path, data: Path | None) -> Path:
    """A run of 2 of its 4 episodes (the header says 4 planned): what a resume continues."""
    run_dir = tmp_path / "run"
    assert _finish(_scripted(run_dir, data))[0] == 0
    lines = (run_dir / "episodes.jsonl").read_text().splitlines()
    (run_dir / "episodes.jsonl").write_text("\n".join(lines[:2]) + "\n")
    return run_dir


@pytest.mark.parametrize(
    ("relative", "edit"),
    [
        ("prompts/saycan_examples.jsonl", lambda text: text.replace("Put a pillow on an ottoman.", "Put it there.")),
        ("tasks/benchmark.jsonl", lambda text: text.replace('"repeat_idx": 1,', '"repeat_idx": 2,', 1)),
    ],
)
def test_a_resume_after_an_input_file_changed_is_refused(tmp_path: Path, relative: str, edit: object) -> None:
    data = _data_copy(tmp_path)
    run_dir = _half_run(tmp_path, data)
    header = read_header(run_dir)
    before_sha = _sha(data / relative)
    assert header.inputs[f"data/{relative}"] == before_sha
    episodes_before = (run_dir / "episodes.jsonl").read_bytes()
    target = data / relative
    assert callable(edit)
    changed = edit(target.read_text())
    assert changed != target.read_text()
    target.write_text(changed)
    code, _, error = _finish(_scripted(run_dir, data))
    assert code == 2 and "Traceback" not in error
    assert f"data/{relative} changed since the run started (sha256 {before_sha[:12]}" in error
    assert _sha(target)[:12] in error
    assert (run_dir / "episodes.jsonl").read_bytes() == episodes_before


def test_every_file_a_run_reads_is_hashed(tmp_path: Path) -> None:
    inputs = input_hashes()
    expected = {
        "data/tasks/benchmark.jsonl",
        "data/tasks/memory.jsonl",
        "data/prompts/saycan_examples.jsonl",
        "data/memory_bank/train.parquet",
        "data/intrusion/level_2.parquet",
        "data/clean/test.parquet",
        "talkdem/planner/prompts/saycan_header.txt",
        "talkdem/planner/prompts/cot.txt",
        "talkdem/planner/prompts/VERSION",
    }
    assert expected <= set(inputs)
    assert all(len(v) == 64 and set(v) <= HEX for v in inputs.values())
    assert inputs["data/tasks/benchmark.jsonl"] == _sha(repo_root() / "data" / "tasks" / "benchmark.jsonl")
    # A scored run (plans from elsewhere) reads the tasks and instructions, not the planner's prompts.
    external = input_hashes(planner=False)
    assert "data/tasks/benchmark.jsonl" in external and "data/prompts/saycan_examples.jsonl" not in external


def test_the_spec_takes_every_planner_setting_and_derives_the_keys() -> None:
    from dataclasses import fields

    config = SayCanConfig(max_steps=7)
    settings = planner_settings(config)
    assert set(settings) == {f.name for f in fields(SayCanConfig)} and settings["max_steps"] == 7
    spec = RunSpec.for_run(config, load_strategy("vanilla"), backend_args={"backend": "x", "threads": 2})
    header = spec.header(model={"backend": "x", "name": "m", "revision": ""}, planned_episodes=3)
    assert header.status == "running" and header.inputs == spec.inputs
    assert header.config["max_steps"] == 7 and header.config["backend_args"] == {"backend": "x", "threads": 2}
    assert "config.max_steps" in OUTCOME_KEYS and "inputs" in OUTCOME_KEYS
    assert "config.log_top" not in OUTCOME_KEYS  # logging the best skills changes no outcome
    assert set(spec.resume_keys) > set(OUTCOME_KEYS) and "config.conditions" in spec.merge_keys


def test_a_resume_on_another_code_revision_needs_the_flag_and_records_both(tmp_path: Path) -> None:
    run_dir = _half_run(tmp_path, None)
    header_path = run_dir / "header.json"
    stored = json.loads(header_path.read_text())
    current = stored["code_revision"]
    stored["code_revision"] = "0" * 40
    header_path.write_text(json.dumps(stored))
    episodes_before = (run_dir / "episodes.jsonl").read_bytes()
    code, _, error = _finish(_scripted(run_dir, None))
    assert code == 2 and "Traceback" not in error
    assert "code revision 000000000000" in error and "--continue-on-new-revision" in error
    assert (run_dir / "episodes.jsonl").read_bytes() == episodes_before
    code, output, error = _finish(_scripted(run_dir, None, "--continue-on-new-revision"))
    assert code == 0, error
    assert "2 episodes run, 2 resumed" in output
    header = read_header(run_dir)
    assert header.code_revisions == ("0" * 40, current) and header.code_revision == current
    assert header.status == "complete"


def test_status_is_running_then_complete_and_incomplete_when_stopped(tmp_path: Path) -> None:
    run_dir = tmp_path / "run"
    process = _scripted(run_dir, None, delay=0.4)  # ~5 s per episode
    episodes = run_dir / "episodes.jsonl"
    deadline = time.time() + 120
    while time.time() < deadline and not (episodes.exists() and episodes.stat().st_size):
        time.sleep(0.05)
    assert read_header(run_dir).status == "running"
    process.send_signal(signal.SIGINT)  # Ctrl-C: the run stops cleanly and says it is incomplete
    code, _, _ = _finish(process)
    assert code != 0
    assert read_header(run_dir).status == "incomplete"
    assert len(read_episodes(run_dir)) < 4
    assert _finish(_scripted(run_dir, None))[0] == 0
    assert read_header(run_dir).status == "complete" and len(read_episodes(run_dir)) == 4


def _header_with(tmp_path: Path, **changes: object) -> Path:
    base = RunSpec.for_run(SayCanConfig(), load_strategy("vanilla")).header(
        model={"backend": "b", "name": "m", "revision": ""}, planned_episodes=4
    )
    data = base.to_json()
    for key, value in changes.items():
        if key.startswith("config."):
            data["config"][key.removeprefix("config.")] = value
        else:
            data[key] = value
    (tmp_path / "header.json").write_text(json.dumps(data))
    return tmp_path / "header.json"


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        ({"config.max_steps": -5}, "'config.max_steps' must be a positive integer, got -5"),
        ({"config.max_steps": 2.7}, "'config.max_steps' must be a positive integer, got 2.7"),
        ({"config.max_steps": True}, "'config.max_steps' must be a positive integer, got True"),
        ({"config.scoring": "median"}, "'config.scoring' must be one of 'sum', 'mean'"),
        ({"config.mask_failed": "yes"}, "'config.mask_failed' must be true or false"),
        ({"config.planned_episodes": -1}, "'config.planned_episodes' must be a non-negative integer"),
        ({"config.limit": 0}, "'config.limit' must be a positive integer or null"),
        ({"config.conditions": "clean"}, "'config.conditions' must be a list of strings"),
        ({"config.shard": "5/3"}, "'config.shard' must be I/N"),
        ({"config.strategy_args": {"k": {"nested": 1}}}, "'config.strategy_args' must map names to strings, numbers"),
        ({"status": "done"}, "'status' must be one of 'running', 'complete', 'incomplete'"),
        ({"inputs": {"data/x": "abc"}}, "'inputs' must map file names to sha256 hex digests"),
        ({"dataset_hash": "not-a-hash"}, "'dataset_hash' must be a sha256 hex digest"),
        ({"code_revisions": "abc"}, "'code_revisions' must be a list of strings"),
        ({"runtimes": [{"cpu": 3}]}, "'runtimes' must be a list of objects mapping names to strings"),
        ({"runtimes": {"cpu": "x"}}, "'runtimes' must be a list of objects mapping names to strings"),
        ({"created": "yesterday"}, "'created' must be an ISO date and time"),
    ],
)
def test_every_header_field_is_validated_on_read(tmp_path: Path, changes: dict[str, object], message: str) -> None:
    path = _header_with(tmp_path, **changes)
    with pytest.raises(RecordError, match="^" + re.escape(str(path)) + ": .*" + re.escape(message)):
        read_header(tmp_path)


def test_a_valid_new_header_round_trips(tmp_path: Path) -> None:
    _header_with(tmp_path)
    header = read_header(tmp_path)
    assert header == RunHeader.from_json(header.to_json())


def test_the_committed_runs_still_read(tmp_path: Path) -> None:
    # A sweep in progress keeps its shards under an ignored `.sweep/` folder (running, never committed).
    headers = sorted(p for p in (repo_root() / "results").rglob("header.json") if ".sweep" not in p.parts)
    assert headers, "the committed baseline runs are expected under results/"
    for path in headers:
        header = read_header(path.parent)
        if header.inputs:
            # Written by the run spec: a committed run was stopped (never left `running`), and its status says
            # whether it is finished; long runs are committed as they grow, over several sittings.
            assert header.status in ("complete", "incomplete"), path
            progress = run_progress(path.parent)
            assert progress.complete == (header.status == "complete"), path
        else:
            assert header.status == ""  # written before either existed: unknown


def test_resuming_a_run_without_input_hashes_says_they_are_unknown(tmp_path: Path) -> None:
    run_dir = _half_run(tmp_path, None)
    stored = json.loads((run_dir / "header.json").read_text())
    for key in ("inputs", "status", "code_revisions"):
        stored.pop(key)
    for key in ("strategy_args", "backend_args", "log_top"):
        stored["config"].pop(key)
    (run_dir / "header.json").write_text(json.dumps(stored))  # as an older version wrote it
    code, output, error = _finish(_scripted(run_dir, None))
    assert code == 0, error
    assert "2 episodes run, 2 resumed" in output
    assert "records no input file hashes" in error and "unknown" in error
    header = read_header(run_dir)
    assert header.inputs == {} and header.status == "complete"  # unknown stays unknown: nothing is made up


def test_each_sittings_runtime_is_recorded_once(tmp_path: Path) -> None:
    import platform

    from talkdem.runs.runtime import cpu_model

    run_dir = _half_run(tmp_path, None)
    (here,) = read_header(run_dir).runtimes
    # The scripted model describes no libraries: what is left is the machine's, and nothing names the machine.
    assert here == {
        "python": platform.python_version(),
        "platform": f"{platform.system()} {platform.machine()}",
        "cpu": cpu_model(),
    }
    assert platform.node() not in json.dumps(here)
    header_path = run_dir / "header.json"
    stored = json.loads(header_path.read_text())
    elsewhere = {**here, "cpu": "Another CPU", "llama_cpp_system_info": "CPU : AVX2 = 1 |"}
    stored["runtimes"] = [elsewhere]  # the first sitting ran on another machine
    header_path.write_text(json.dumps(stored))
    assert _finish(_scripted(run_dir, None))[0] == 0
    assert read_header(run_dir).runtimes == (elsewhere, here)
    lines = (run_dir / "episodes.jsonl").read_text().splitlines()
    (run_dir / "episodes.jsonl").write_text(lines[0] + "\n")
    assert _finish(_scripted(run_dir, None))[0] == 0  # a third sitting here adds nothing
    assert read_header(run_dir).runtimes == (elsewhere, here)


def test_split_and_merge_keep_status_inputs_and_revisions(tmp_path: Path) -> None:
    from talkdem.runs.shards import merge_runs, split_run

    run_dir = _half_run(tmp_path, None)
    inputs = read_header(run_dir).inputs
    shards = split_run(run_dir, 2, tmp_path / "shards")
    for shard in shards:
        header = read_header(shard.run_dir)
        assert header.status == ("complete" if shard.seeded == shard.planned else "incomplete")
        assert header.inputs == inputs
    first, second = (s.run_dir for s in shards)
    path = second / "header.json"
    stored = json.loads(path.read_text())
    current = stored["code_revision"]
    stored["code_revision"] = "0" * 40  # the second shard was started on another machine's checkout
    (here,) = stored["runtimes"]
    elsewhere = {**here, "cpu": "Another CPU"}
    stored["runtimes"] = [elsewhere]
    path.write_text(json.dumps(stored))
    for index, folder in ((1, first), (2, second)):
        process = _scripted(folder, None, "--shard", f"{index}/2", "--continue-on-new-revision")
        assert _finish(process)[0] == 0
        assert read_header(folder).status == "complete"
    merged = merge_runs(tmp_path / "merged", [first, second])
    header = read_header(merged.out)
    assert header.status == "complete" and header.inputs == inputs
    assert sorted(header.code_revisions) == sorted([current, "0" * 40])
    assert header.runtimes == (here, elsewhere)  # every runtime that wrote episodes, in shard order
    # Shards whose input files differ are not one run.
    stored = json.loads(path.read_text())
    stored["inputs"]["data/tasks/benchmark.jsonl"] = "f" * 64
    path.write_text(json.dumps(stored))
    with pytest.raises(ValueError, match=r"data/tasks/benchmark\.jsonl changed between the shards"):
        merge_runs(tmp_path / "merged-again", [first, second])


def test_a_scored_run_records_the_files_it_read_and_its_status(tmp_path: Path) -> None:
    from talkdem.runs.external import record_plans
    from talkdem.runs.sampling import select_episodes
    from talkdem.schema import parse_conditions
    from talkdem.tasks import get_task

    plans = {e.id: get_task(e.task_id).reference_plan for e in select_episodes(parse_conditions("clean"), 2)}
    record_plans(plans, tmp_path / "run", "p")
    header = read_header(tmp_path / "run")
    assert header.status == "complete" and header.inputs == input_hashes(planner=False)


def test_a_strategys_arguments_are_its_plain_settings(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    import numpy as np

    from care.strategy import ContextAwareRetrieval
    from talkdem.instructions import load_memory_bank
    from talkdem.runs.spec import strategy_arguments

    monkeypatch.setenv("TALKDEM_CACHE_DIR", str(tmp_path))

    def encode(texts: object) -> np.ndarray:  # type: ignore[type-arg]
        return np.ones((len(texts), 4)) / 2  # type: ignore[arg-type]

    care = ContextAwareRetrieval(memory=load_memory_bank()[:10], k=2, encode=encode)
    # not the memory bank, the encoder or the embeddings
    assert strategy_arguments(care) == {"k": 2, "order": "best_last", "dedupe": False}
    assert strategy_arguments(load_strategy("vanilla")) == {}


@pytest.mark.parametrize("steps", [-5, 2.7])
def test_report_refuses_an_impossible_step_limit_in_one_line(tmp_path: Path, steps: float) -> None:
    from talkdem.runs.external import record_plans
    from talkdem.runs.sampling import select_episodes
    from talkdem.schema import parse_conditions
    from talkdem.tasks import get_task

    run_dir = tmp_path / "run"
    plans = {e.id: get_task(e.task_id).reference_plan for e in select_episodes(parse_conditions("clean"), 2)}
    record_plans(plans, run_dir, "p")
    stored = json.loads((run_dir / "header.json").read_text())
    stored["config"]["max_steps"] = steps
    (run_dir / "header.json").write_text(json.dumps(stored))
    command = [sys.executable, "-m", "talkdem", "report", str(run_dir), "--out", str(tmp_path / "r"), "--no-plots"]
    result = subprocess.run(command, capture_output=True, text=True, timeout=300)
    assert result.returncode == 2 and "Traceback" not in result.stderr
    assert result.stderr.strip().splitlines() == [
        f"talkdem report: error: {run_dir / 'header.json'}: field 'config.max_steps' must be a positive integer, "
        f"got {steps}"
    ]
    assert not (tmp_path / "r").exists()


def test_the_report_names_an_input_file_that_changed_since_the_run(tmp_path: Path) -> None:
    data = _data_copy(tmp_path)
    run_dir = tmp_path / "run"
    assert _finish(_scripted(run_dir, data))[0] == 0
    tasks = data / "tasks" / "benchmark.jsonl"
    before = _sha(tasks)
    tasks.write_text(tasks.read_text().replace('"repeat_idx": 1,', '"repeat_idx": 2,', 1))
    command = [sys.executable, "-m", "talkdem", "report", str(run_dir), "--out", str(tmp_path / "r"), "--no-plots"]
    env = {**os.environ, "TALKDEM_DATA_DIR": str(data)}
    result = subprocess.run(command, capture_output=True, text=True, timeout=300, env=env)
    assert result.returncode == 0, result.stderr
    assert (
        f"input files changed since the run: data/tasks/benchmark.jsonl (sha256 {before[:12]}... -> " in result.stderr
    )
