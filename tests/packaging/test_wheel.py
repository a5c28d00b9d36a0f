"""The package as a user installs it: a wheel built from the project's files, installed away from the checkout,
runs the benchmark's commands from another folder (no `../shared`, no `data/` beside it)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest
from wheel_helpers import PIP, build_wheel

from talkdem.paths import repo_root


@pytest.fixture(scope="module")
def installed(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A wheel built from a copy of the project's files (so the checkout gets no build/ folder), installed
    with --no-deps into its own folder: the dependencies come from this environment, the code and data
    only from the wheel."""
    root = tmp_path_factory.mktemp("wheel")
    wheel = build_wheel(root)
    pip = PIP
    names = zipfile.ZipFile(wheel).namelist()
    for needed in (
        "talk_dem.py",
        "talkdem/_bundled/data/README.md",
        "talkdem/_bundled/data/tasks/benchmark.jsonl",
        "talkdem/_bundled/data/prompts/saycan_examples.jsonl",
        "talkdem/_bundled/evaluate_talkdem/evaluate_talkdem.py",
        "talkdem/planner/prompts/VERSION",
        "talkdem/skills/categories.json",
        "talkdem/viewer/assets/viewer.js",
        "talkdem/viewer/assets/viewer.css",
    ):
        assert needed in names, f"the wheel lacks {needed}"
    subprocess.run([*pip, "install", "--no-deps", "--target", str(root / "site"), str(wheel)], check=True)
    assert (
        not (repo_root() / "build").exists() or (repo_root() / "build").stat().st_mtime < wheel.stat().st_mtime - 3600
    )
    return root


def _talkdem(installed: Path, *args: str, stdin: str | None = None) -> subprocess.CompletedProcess[str]:
    env = {k: v for k, v in os.environ.items() if not k.startswith("TALKDEM_")}
    env |= {"PYTHONPATH": str(installed / "site"), "HF_HUB_OFFLINE": "1", "HF_DATASETS_CACHE": str(installed / "hf")}
    elsewhere = installed / "elsewhere"
    elsewhere.mkdir(exist_ok=True)
    command = [sys.executable, "-c", "import sys; from talkdem.cli import main; sys.exit(main())", *args]
    return subprocess.run(command, cwd=elsewhere, env=env, input=stdin, capture_output=True, text=True, timeout=600)


def _ok(result: subprocess.CompletedProcess[str]) -> str:
    assert result.returncode == 0, result.stderr[-2000:]
    return result.stdout


@pytest.mark.slow
def test_the_installed_package_is_the_wheel(installed: Path) -> None:
    out = _ok(_talkdem(installed, "tasks", "--set", "memory", "--format", "jsonl"))
    assert len(out.splitlines()) == 100
    code = "import talkdem, talk_dem; print(talkdem.__file__); print(talk_dem.__file__)"
    env = {**os.environ, "PYTHONPATH": str(installed / "site")}
    where = subprocess.run([sys.executable, "-c", code], env=env, cwd=installed, capture_output=True, text=True)
    assert all(line.startswith(str(installed / "site")) for line in where.stdout.splitlines()), where.stdout


@pytest.mark.slow
def test_simulate_score_and_report_from_the_wheel(installed: Path) -> None:
    task = json.loads(_ok(_talkdem(installed, "tasks", "--format", "jsonl")).splitlines()[0])
    trace = json.loads(
        _ok(
            _talkdem(
                installed,
                "simulate",
                "--task",
                task["task_id"],
                "--plan-file",
                "-",
                stdin=json.dumps(task["reference_plan"]),
            )
        )
    )
    assert trace["success"] is True
    plans = installed / "plans.jsonl"
    plans.write_text(json.dumps({"episode_id": f"{task['task_id']}:clean:0", "plan": task["reference_plan"]}) + "\n")
    _ok(_talkdem(installed, "score", str(plans), "--out", str(installed / "run"), "--name", "wheel-check"))
    _ok(_talkdem(installed, "report", str(installed / "run"), "--out", str(installed / "report"), "--no-plots"))
    report = (installed / "report" / "report.md").read_text()
    assert "wheel-check" in report and str(installed) not in report
    assert "Llama-3.1-8B-Instruct (paper)" in report, "the paper's figures ship with the wheel"
    _ok(_talkdem(installed, "view", str(installed / "run"), "--out", str(installed / "viewer")))
    page = (installed / "viewer" / "index.html").read_text()
    assert "TALKDEM_VIEWER_CHUNK" in page  # the viewer's script ships in the wheel


@pytest.mark.slow
def test_talk_dem_load_and_the_evaluate_module_from_the_wheel(installed: Path) -> None:
    code = (
        "import talk_dem, talkdem.paths as p\n"
        "print(talk_dem.load('intrusion', 2).num_rows)\n"
        "print((p.evaluate_module_dir() / 'evaluate_talkdem.py').is_file())\n"
    )
    env = {k: v for k, v in os.environ.items() if not k.startswith("TALKDEM_")}
    env |= {"PYTHONPATH": str(installed / "site"), "HF_HUB_OFFLINE": "1", "HF_DATASETS_CACHE": str(installed / "hf")}
    result = subprocess.run([sys.executable, "-c", code], env=env, cwd=installed, capture_output=True, text=True)
    assert result.stdout.split() == ["300", "True"], result.stderr[-2000:]


@pytest.mark.slow
def test_run_from_the_wheel(installed: Path) -> None:
    args = ["run", "--backend", "hf", "--model", "default", "--limit", "1", "--conditions", "clean"]
    result = _talkdem(installed, *args, "--max-steps", "2", "--out", str(installed / "smol"), "--no-progress")
    assert "1 episodes run" in _ok(result)
