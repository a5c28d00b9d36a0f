"""TALK-Dem as an inspect_ai task: a scripted mock model (unit test of the task and the importer), then a real
local model through inspect's llama-cpp-python provider and `talkdem report` on the imported run (slow)."""

from __future__ import annotations

import json
import socket
import subprocess
import sys
import time
import urllib.request
from collections.abc import Iterator
from pathlib import Path

import pytest
from inspect_ai import eval as inspect_eval
from inspect_ai.model import ModelOutput, ModelUsage, get_model

from talkdem.cli import main
from talkdem.env import select
from talkdem.evals.inspect_task import talkdem
from talkdem.runs import read_episodes, read_header
from talkdem.tasks import get_task


def _scripted(plans: list[tuple[str, ...]]) -> list[ModelOutput]:
    outputs = []
    for plan in plans:
        for skill in plan:
            output = ModelOutput.for_tool_call("mockllm/model", "act", {"skill": skill})
            output.usage = ModelUsage(input_tokens=1, output_tokens=1, total_tokens=2)  # no tokenizer download
            outputs.append(output)
    return outputs


def test_a_scripted_agent_is_scored_by_the_goal_check_and_imported(tmp_path: Path) -> None:
    episodes = select("clean", limit=2)
    first = get_task(episodes[0].task_id).reference_plan
    wrong = ("done",)  # the second agent stops at once
    model = get_model("mockllm/model", custom_outputs=_scripted([first, wrong]))
    (log,) = inspect_eval(
        talkdem(conditions="clean", limit=2), model=model, log_dir=str(tmp_path / "logs"), display="none", max_samples=1
    )
    assert log.status == "success"
    values = {str(s.id): s.scores["goal_check"].value for s in log.samples or []}
    assert values == {episodes[0].id: "C", episodes[1].id: "I"}
    log_file = Path(log.location)
    assert main(["import-inspect", str(log_file), "--out", str(tmp_path / "run")]) == 0
    header = read_header(tmp_path / "run")
    assert header.model["backend"] == "inspect" and header.model["name"] == "mockllm/model"
    assert header.config["log"] == log_file.name and str(tmp_path) not in json.dumps(header.to_json())
    records = read_episodes(tmp_path / "run")
    assert [(r.episode_id, r.plan, r.success) for r in records] == [
        (episodes[0].id, first, True),
        (episodes[1].id, wrong, False),
    ]
    assert main(["report", str(tmp_path / "run"), "--out", str(tmp_path / "report"), "--no-plots"]) == 0


def test_an_import_refuses_a_log_whose_score_disagrees(tmp_path: Path) -> None:
    from inspect_ai.log import read_eval_log, write_eval_log

    episode = select("clean", limit=1)[0]
    model = get_model("mockllm/model", custom_outputs=_scripted([get_task(episode.task_id).reference_plan]))
    (log,) = inspect_eval(talkdem(limit=1), model=model, log_dir=str(tmp_path / "logs"), display="none", max_samples=1)
    edited = read_eval_log(log.location)
    assert edited.samples
    edited.samples[0].scores["goal_check"].value = "I"
    write_eval_log(edited, str(tmp_path / "edited.eval"))
    assert main(["import-inspect", str(tmp_path / "edited.eval"), "--out", str(tmp_path / "run")]) == 2


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        port: int = probe.getsockname()[1]
    return port


@pytest.fixture
def llama_server(tmp_path: Path) -> Iterator[str]:
    from talkdem.llm.interface.models import FAST_TEST_MODEL, model_path

    port, log = _free_port(), tmp_path / "server.log"
    command = [sys.executable, "-m", "llama_cpp.server", "--model", str(model_path(FAST_TEST_MODEL))]
    command += ["--model_alias", "smollm2", "--host", "127.0.0.1", "--port", str(port), "--n_ctx", "4096"]
    command += ["--n_threads", "1", "--chat_format", "chatml-function-calling", "--verbose", "False"]
    with log.open("ab") as out:
        process = subprocess.Popen(command, stdout=out, stderr=subprocess.STDOUT)
    url = f"http://127.0.0.1:{port}/v1"
    opener = urllib.request.build_opener(urllib.request.ProxyHandler({}))
    try:
        deadline = time.monotonic() + 120
        while True:
            if process.poll() is not None:
                raise RuntimeError(f"the server exited: {log.read_text()[-2000:]}")
            try:
                with opener.open(url + "/models", timeout=5):
                    break
            except OSError:
                if time.monotonic() > deadline:
                    raise TimeoutError(log.read_text()[-2000:]) from None
                time.sleep(0.5)
        yield url
    finally:
        process.terminate()
        try:
            process.wait(timeout=15)
        except subprocess.TimeoutExpired:
            process.kill()


@pytest.mark.slow
def test_inspect_eval_on_a_local_model_imports_into_a_run_report_accepts(
    llama_server: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("NO_PROXY", "127.0.0.1,localhost")
    import talkdem.evals.inspect_task as task_module

    task_file = Path(task_module.__file__).resolve()
    root = task_file.parents[2]  # inspect takes the task file relative to where it runs
    command = [sys.executable, "-m", "inspect_ai", "eval", task_file.relative_to(root).as_posix()]
    command += ["-T", "conditions=clean,intrusion:3", "-T", "limit=1", "-T", "max_steps=3"]  # report needs clean twins
    command += ["--model", "llama-cpp-python/smollm2"]
    command += ["--model-base-url", llama_server, "--log-dir", str(tmp_path / "logs"), "--display", "none"]
    command += ["--max-tokens", "48", "--temperature", "0"]
    done = subprocess.run(command, capture_output=True, text=True, timeout=600, cwd=root)
    assert done.returncode == 0, done.stderr[-3000:]
    (log_file,) = (tmp_path / "logs").glob("*.eval")
    assert main(["import-inspect", str(log_file), "--out", str(tmp_path / "run")]) == 0
    records = read_episodes(tmp_path / "run")
    assert [r.episode_id for r in records] == [i.id for i in select("clean,intrusion:3", limit=1)]
    assert all(1 <= len(r.plan) <= 3 for r in records)
    assert main(["report", str(tmp_path / "run"), "--out", str(tmp_path / "report"), "--no-plots"]) == 0
