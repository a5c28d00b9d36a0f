"""The dataset by Hub id, read from the Hugging Face cache exactly as `snapshot_download` lays it out; no
network in tests: the copy is placed in a cache folder made by the test, and HF_HUB_OFFLINE is set."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

from builders.push import upload_plan
from talkdem.hub import is_repo_id, names_hub_dataset
from talkdem.paths import repo_root

COMMIT = "0123456789abcdef0123456789abcdef01234567"


def _cache_with_a_pushed_copy(root: Path) -> Path:
    """A Hub cache holding `org/talk-dem` at one revision, with exactly the files `talkdem push` uploads."""
    repo = root / "hub" / "datasets--org--talk-dem"
    snapshot = repo / "snapshots" / COMMIT
    for name in upload_plan(repo_root() / "data"):
        (snapshot / name).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(repo_root() / "data" / name, snapshot / name)
    (repo / "refs").mkdir(parents=True)
    (repo / "refs" / "main").write_text(COMMIT)
    return root / "hub"


def _talkdem(cache: Path, data: str, *args: str) -> subprocess.CompletedProcess[str]:
    env = {k: v for k, v in os.environ.items() if not k.startswith(("TALKDEM_", "HF_"))}
    env |= {"HF_HUB_CACHE": str(cache), "HF_HUB_OFFLINE": "1", "TALKDEM_DATA_DIR": data}
    code = "import sys; from talkdem.cli import main; sys.exit(main())"
    return subprocess.run([sys.executable, "-c", code, *args], env=env, capture_output=True, text=True, timeout=300)


def test_every_command_can_run_on_a_hub_copy(tmp_path: Path) -> None:
    cache = _cache_with_a_pushed_copy(tmp_path)
    tasks = _talkdem(cache, "org/talk-dem", "tasks", "--set", "memory", "--format", "jsonl")
    assert tasks.returncode == 0, tasks.stderr
    assert len(tasks.stdout.splitlines()) == 100
    first = tasks.stdout.splitlines()[0]
    plan = tmp_path / "plan.json"
    record = json.loads(first)
    plan.write_text(json.dumps(record["reference_plan"]))
    simulated = _talkdem(cache, "org/talk-dem", "simulate", "--task", record["task_id"], "--plan-file", str(plan))
    assert simulated.returncode == 0 and json.loads(simulated.stdout)["success"] is True, simulated.stderr


def test_offline_without_a_cached_copy_fails_at_once_with_one_line(tmp_path: Path) -> None:
    result = _talkdem(tmp_path / "empty-cache", "org/not-cached", "tasks")
    assert result.returncode == 2
    assert "org/not-cached: not in the Hugging Face cache and HF_HUB_OFFLINE is set" in result.stderr
    assert "Traceback" not in result.stderr


def test_repo_ids_and_folders() -> None:
    assert is_repo_id("org/talk-dem") and not is_repo_id("talk-dem") and not is_repo_id("a/b/c")
    assert not is_repo_id("../x") and not is_repo_id(str(repo_root() / "data"))
    assert not names_hub_dataset("data") and names_hub_dataset("org/not-a-local-folder")
