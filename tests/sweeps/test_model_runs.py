"""A sweep on a real model (SmolLM2-135M, llama.cpp, 1 thread), 2 tasks x 2 conditions x 2 strategies: run by
two local worker processes, and on a local Ray cluster (127.0.0.1, 2 CPUs, two actors), each run directory holds
exactly the episodes of a serial `talkdem run` with the same settings, in the same order.

What is compared: every field of every episode record but `timing` (wall-clock seconds, different in any two
runs), and the header's outcome keys; the headers differ only in `created` and in the merge's `merged_from`."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

from talkdem.runs import read_header
from talkdem.runs.spec import MERGE_KEYS, differences
from talkdem.sweeps import load_sweep, run_sweep

pytestmark = pytest.mark.slow

SPEC = """\
out: OUT
models: [smollm2-135m-instruct]
strategies: [vanilla, ap]
conditions: [clean, intrusion:1]
tasks: 2
planner: {max_steps: 4}
"""


def _records(run_dir: Path) -> list[dict[str, Any]]:
    lines = (run_dir / "episodes.jsonl").read_text(encoding="utf-8").splitlines()
    return [{k: v for k, v in json.loads(line).items() if k != "timing"} for line in lines]


@pytest.fixture(scope="module")
def serial(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """The serial runs: `talkdem run` of each (model, strategy), as the dry run prints it."""
    root = tmp_path_factory.mktemp("serial")
    spec_file = root / "sweep.yaml"
    spec_file.write_text(SPEC.replace("OUT", str(root / "runs")))
    runs = {}
    for run in load_sweep(spec_file).runs:
        command = [sys.executable, "-m", "talkdem", "run", *run.command(out=run.run_dir, threads=1), "--no-progress"]
        done = subprocess.run(command, capture_output=True, text=True, timeout=900, check=False)
        assert done.returncode == 0, done.stderr[-2000:]
        runs[run.name] = run.run_dir
    return runs


def _same_as_serial(out: Path, serial: dict[str, Path]) -> None:
    for name, reference in serial.items():
        swept = out / name
        assert len(_records(reference)) == 4
        assert _records(swept) == _records(reference), name
        first, other = read_header(reference), read_header(swept)
        assert differences(first, other, MERGE_KEYS) == []
        assert other.status == "complete" and other.config["merged_from"] == ["1/2", "2/2"]
        plain = {k: v for k, v in other.to_json().items() if k != "created"}
        plain["config"] = {k: v for k, v in plain["config"].items() if k != "merged_from"}
        assert plain == {k: v for k, v in first.to_json().items() if k != "created"}


def _spec(tmp_path: Path) -> Path:
    path = tmp_path / "sweep.yaml"
    path.write_text(SPEC.replace("OUT", str(tmp_path / "out")))
    return path


def test_two_local_workers_equal_the_serial_runs(tmp_path: Path, serial: dict[str, Path]) -> None:
    spec = load_sweep(_spec(tmp_path))
    result = run_sweep(spec, workers=2, threads=1, progress=False)
    assert result.failures == () and len(result.complete) == 2
    _same_as_serial(spec.out, serial)


def test_a_local_ray_cluster_equals_the_serial_runs(tmp_path: Path, serial: dict[str, Path]) -> None:
    ray = pytest.importorskip("ray", reason="the `ray` extra is not installed")
    ray.init(address="local", num_cpus=2, include_dashboard=False, _node_ip_address="127.0.0.1")
    try:
        spec = load_sweep(_spec(tmp_path))
        result = run_sweep(spec, threads=1, ray="auto", progress=False)
    finally:
        ray.shutdown()
    assert result.failures == () and len(result.complete) == 2
    # Two actors (2 CPUs, 1 each) ran the four jobs (2 runs x 2 shards): each loaded the model once.
    assert result.model_loads == {"smollm2-135m-instruct": (2, 4)}
    _same_as_serial(spec.out, serial)
