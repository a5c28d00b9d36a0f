"""Runs through the served scoring client: concurrency, several servers, shards and merge, a killed server and
resume. The server is `wire_server.py`, a stand-in vLLM (token-id prompts, echoed log-probabilities) scoring
like the scripted test model: what is tested here is the client and the run machinery, where a real model would
only add time (agreement with a real model through a real server: tests/llm/test_served_scoring.py).
"""

from __future__ import annotations

import json
import shutil
import socket
import subprocess
import sys
import time
import urllib.request
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from talkdem.cli import main
from talkdem.llm.interface.models import FAST_TEST_MODEL
from talkdem.runs.store import read_episodes, read_header, run_progress

SERVER = Path(__file__).parent / "wire_server.py"
RUN = ["run", "--backend", "openai", "--model", "served-test", "--model-arg", f"tokenizer={FAST_TEST_MODEL}"]
RUN += ["--no-progress"]
SELECTION = ["--conditions", "clean,intrusion:1", "--limit", "3", "--max-steps", "4"]
_NO_PROXY = urllib.request.build_opener(urllib.request.ProxyHandler({}))


def _free_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as probe:
        probe.bind(("127.0.0.1", 0))
        port: int = probe.getsockname()[1]
    return port


class WireServer:
    def __init__(self, log: Path, delay: float = 0.0) -> None:
        self.port, self.log, self.delay = _free_port(), log, delay
        self.url = f"http://127.0.0.1:{self.port}/v1"
        self.process: subprocess.Popen[bytes] | None = None

    def start(self) -> None:
        command = [sys.executable, str(SERVER), str(self.port), str(self.log), str(self.delay)]
        self.process = subprocess.Popen(command, stderr=subprocess.DEVNULL)
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline:
            try:
                with _NO_PROXY.open(self.url + "/models", timeout=2):
                    return
            except OSError:
                time.sleep(0.1)
        raise TimeoutError("the wire server did not start")

    def kill(self) -> None:
        if self.process is not None:
            self.process.kill()
            self.process.wait(timeout=30)

    def requests(self) -> list[dict[str, Any]]:
        if not self.log.exists():
            return []
        return [json.loads(line) for line in self.log.read_text().splitlines()]


@pytest.fixture
def servers(tmp_path: Path) -> Iterator[list[WireServer]]:
    started = [WireServer(tmp_path / f"server{i}.jsonl") for i in range(2)]
    for server in started:
        server.start()
    try:
        yield started
    finally:
        for server in started:
            server.kill()


def _records(run_dir: Path) -> list[dict[str, Any]]:
    """The episodes in file order, without timings (the only field that differs between equal runs)."""
    return [{k: v for k, v in e.to_json().items() if k != "timing"} for e in read_episodes(run_dir)]


def _run(*args: str) -> int:
    return main([*RUN, *SELECTION, *args])


def test_concurrency_and_several_servers_give_the_records_of_one_at_a_time(
    servers: list[WireServer], tmp_path: Path
) -> None:
    first, second = servers
    assert _run("--base-url", first.url, "--out", str(tmp_path / "one")) == 0
    reference = _records(tmp_path / "one")
    assert len(reference) == 6 and all(len(r["plan"]) >= 2 for r in reference)
    first.log.unlink()
    assert (
        _run("--base-url", first.url, "--base-url", second.url, "--concurrency", "4", "--out", str(tmp_path / "four"))
        == 0
    )
    assert _records(tmp_path / "four") == reference, "same records, in the selection's order"
    # every episode stayed on one server, and both servers were used
    seen = [{r["instruction"] for r in server.requests()} for server in servers]
    assert seen[0] and seen[1] and not seen[0] & seen[1]
    assert all(r["prompts"] > 100 for server in servers for r in server.requests()), "one request per step"
    header = read_header(tmp_path / "four")
    assert header.planner == "saycan" and header.model["backend"] == "openai"
    served = header.config["served"]
    assert served["servers"] == sorted([first.url, second.url]) and served["tokenizer"] == FAST_TEST_MODEL
    assert served["scoring_api"] == "completions" and served["served_model"] == "served-test"
    # `--model` naming a local model: its tokenizer is used without a tokenizer model arg
    command = ["run", "--backend", "openai", "--model", FAST_TEST_MODEL, "--no-progress", *SELECTION]
    assert main([*command, "--base-url", first.url, "--out", str(tmp_path / "named")]) == 0
    assert _records(tmp_path / "named") == reference


def test_shards_merge_into_the_unsharded_run_and_bad_merges_are_refused(
    servers: list[WireServer], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    url = servers[0].url
    assert _run("--base-url", url, "--out", str(tmp_path / "whole")) == 0
    for shard in ("1/2", "2/2"):
        out = tmp_path / f"shard{shard[0]}"
        assert _run("--base-url", url, "--concurrency", "2", "--shard", shard, "--out", str(out)) == 0
        assert read_header(out).config["shard"] == shard
    ids = [{r["episode_id"] for r in _records(tmp_path / f"shard{i}")} for i in (1, 2)]
    assert ids[0] and ids[1] and not ids[0] & ids[1]
    assert main(["merge", str(tmp_path / "merged"), str(tmp_path / "shard2"), str(tmp_path / "shard1")]) == 0
    assert _records(tmp_path / "merged") == _records(tmp_path / "whole")
    assert run_progress(tmp_path / "merged").complete
    assert read_header(tmp_path / "merged").config["merged_from"] == ["2/2", "1/2"]
    # the merged run is a run like any other
    assert main(["report", str(tmp_path / "merged"), "--out", str(tmp_path / "report"), "--no-plots"]) == 0
    board = ["leaderboard", str(tmp_path / "merged"), "--out", str(tmp_path / "board"), "--bootstrap", "0"]
    assert main(board) == 0
    assert "served-test" in (tmp_path / "board" / "README.md").read_text()
    capsys.readouterr()

    # incomplete: the missing episodes are named, nothing is written
    assert main(["merge", str(tmp_path / "half"), str(tmp_path / "shard1")]) == 2
    error = capsys.readouterr().err
    assert f"{len(ids[1])} of 6 episodes are missing" in error and sorted(ids[1])[0] in error
    assert not (tmp_path / "half").exists()
    # overlapping: the same shard twice (a copy)
    shutil.copytree(tmp_path / "shard1", tmp_path / "copy1")
    assert main(["merge", str(tmp_path / "x"), str(tmp_path / "shard1"), str(tmp_path / "copy1")]) == 2
    assert "shard 1/2 is named twice" in capsys.readouterr().err
    shutil.copytree(tmp_path / "whole", tmp_path / "whole2")
    assert main(["merge", str(tmp_path / "x"), str(tmp_path / "shard1"), str(tmp_path / "whole2")]) == 2
    assert "overlapping shards" in capsys.readouterr().err
    # mismatched header: another step limit
    other = [*RUN, "--conditions", "clean,intrusion:1", "--limit", "3", "--max-steps", "3"]
    assert main([*other, "--base-url", url, "--shard", "2/2", "--out", str(tmp_path / "other2")]) == 0
    assert main(["merge", str(tmp_path / "x"), str(tmp_path / "shard1"), str(tmp_path / "other2")]) == 2
    assert "config.max_steps: 4 vs 3" in capsys.readouterr().err
    assert not (tmp_path / "x").exists()


def test_a_killed_server_fails_the_run_after_retries_and_the_run_resumes(
    servers: list[WireServer], tmp_path: Path
) -> None:
    assert _run("--base-url", servers[0].url, "--out", str(tmp_path / "reference")) == 0
    slow = WireServer(tmp_path / "slow.jsonl", delay=0.3)
    slow.start()
    out = tmp_path / "interrupted"
    command = [sys.executable, "-m", "talkdem", *RUN, *SELECTION, "--base-url", slow.url, "--out", str(out)]
    run = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.monotonic() + 120
        while time.monotonic() < deadline and not (out / "episodes.jsonl").exists():
            time.sleep(0.05)
        while time.monotonic() < deadline and not (out / "episodes.jsonl").read_text().strip():
            time.sleep(0.05)
        slow.kill()  # mid-run: an episode is on disk, others are not
        _, error = run.communicate(timeout=120)
    finally:
        slow.kill()
        if run.poll() is None:
            run.kill()
    assert run.returncode == 2, error
    assert "no answer after 6 attempts" in error and "Traceback" not in error
    done = len(read_episodes(out))
    assert 1 <= done < 6
    slow.delay = 0.0
    slow.start()  # the same port
    resumed = subprocess.run(command, capture_output=True, text=True, timeout=300)
    assert resumed.returncode == 0, resumed.stderr
    assert f"{done} resumed" in resumed.stdout
    assert _records(out) == _records(tmp_path / "reference")
    slow.kill()
