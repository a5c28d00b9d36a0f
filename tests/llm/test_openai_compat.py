"""The `openai` backend against a real OpenAI-compatible server started here: llama-cpp-python's server on the
embedded SmolLM2-135M GGUF, listening on 127.0.0.1 only. The server is killed and restarted mid-run to check
retries. Needs the `llamacpp` extra (`make test` installs it).
"""

from __future__ import annotations

import http.server
import json
import socket
import subprocess
import sys
import threading
import time
import urllib.request
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from talkdem.llm.backends.openai_compat import EndpointError, LoglikelihoodUnsupportedError, OpenAICompatibleLM
from talkdem.llm.interface.models import FAST_TEST_MODEL, model_path
from talkdem.llm.interface.requests import GenerateRequest, LoglikelihoodRequest
from talkdem.planner import PlannerInput, SayCanConfig, SayCanPlanner
from talkdem.skills import vocabulary
from talkdem.tasks import load_tasks

API_KEY = "talkdem-test-key"
STARTUP_SECONDS = 120.0
_NO_PROXY = urllib.request.build_opener(urllib.request.ProxyHandler({}))
QUESTION = GenerateRequest("Name one fruit that is red. Answer with one word.", max_new_tokens=8)


def _free_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as probe:
        probe.bind(("127.0.0.1", 0))
        port: int = probe.getsockname()[1]
    return port


class LlamaServer:
    """`python -m llama_cpp.server` on one fixed local port, which can be killed and started again."""

    def __init__(self, model: Path, port: int, log: Path) -> None:
        self.model, self.port, self.log = model, port, log
        self.process: subprocess.Popen[bytes] | None = None
        self.base_url = f"http://127.0.0.1:{port}/v1"

    def start(self) -> None:
        command = [sys.executable, "-m", "llama_cpp.server", "--model", str(self.model), "--model_alias", "smollm2"]
        command += ["--host", "127.0.0.1", "--port", str(self.port), "--n_ctx", "4096", "--n_threads", "2"]
        command += ["--api_key", API_KEY, "--verbose", "False"]
        with self.log.open("ab") as log:
            self.process = subprocess.Popen(command, stdout=log, stderr=subprocess.STDOUT)

    def wait_ready(self) -> None:
        deadline = time.monotonic() + STARTUP_SECONDS
        request = urllib.request.Request(self.base_url + "/models", headers={"Authorization": f"Bearer {API_KEY}"})
        while time.monotonic() < deadline:
            assert self.process is not None
            if self.process.poll() is not None:
                raise RuntimeError(f"the server exited ({self.process.returncode}): {self.log.read_text()[-2000:]}")
            try:
                with _NO_PROXY.open(request, timeout=5) as response:
                    if response.status == 200:
                        return
            except OSError:
                time.sleep(0.5)
        raise TimeoutError(f"the server did not answer within {STARTUP_SECONDS} s: {self.log.read_text()[-2000:]}")

    def kill(self) -> None:
        if self.process is not None and self.process.poll() is None:
            self.process.kill()
            self.process.wait(timeout=30)
        self.process = None

    def stop(self) -> None:
        if self.process is not None and self.process.poll() is None:
            self.process.terminate()
            try:
                self.process.wait(timeout=15)
            except subprocess.TimeoutExpired:
                self.kill()
        self.process = None


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[LlamaServer]:
    running = LlamaServer(model_path(FAST_TEST_MODEL), _free_port(), tmp_path_factory.mktemp("server") / "server.log")
    running.start()
    try:
        running.wait_ready()
        yield running
    finally:
        running.stop()


def _client(server: LlamaServer, **options: Any) -> OpenAICompatibleLM:
    options = {"api_key": API_KEY, "timeout": 60.0, "max_retries": 2, "backoff": 0.2, **options}
    return OpenAICompatibleLM("smollm2", base_url=server.base_url, **options)


@pytest.mark.slow
def test_chat_generation_end_to_end(server: LlamaServer) -> None:
    model = _client(server)
    answers = model.generate([QUESTION, GenerateRequest("Say hello.", max_new_tokens=6)])
    assert len(answers) == 2 and all(isinstance(a, str) and a for a in answers)
    assert model.generate([QUESTION]) == answers[:1], "temperature 0: the same answer twice"
    assert model.identity.key() == f"openai:smollm2@{server.base_url}"


@pytest.mark.slow
def test_completions_endpoint_and_stop_strings(server: LlamaServer) -> None:
    model = _client(server, endpoint="completions")
    text = model.generate([GenerateRequest("1, 2, 3, 4,", max_new_tokens=12, stop=(",", "\n"))])[0]
    assert text and "," not in text and "\n" not in text


@pytest.mark.slow
def test_api_key_from_the_environment_and_a_wrong_key_is_not_retried(
    server: LlamaServer, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("OPENAI_API_KEY", API_KEY)
    from_env = OpenAICompatibleLM("smollm2", base_url=server.base_url, max_retries=0)
    assert from_env.generate([QUESTION])[0]
    wrong = _client(server, api_key="not-the-key", max_retries=3)
    waits: list[float] = []
    wrong.sleep = waits.append
    with pytest.raises(EndpointError, match="HTTP 401"):
        wrong.generate([QUESTION])
    assert waits == [], "a client error is not retried"


@pytest.mark.slow
def test_a_dead_server_gives_retries_then_a_clear_error_and_a_restarted_one_is_reached(server: LlamaServer) -> None:
    model = _client(server, max_retries=3, backoff=0.1)
    waits: list[float] = []

    def recorded_sleep(seconds: float) -> None:
        waits.append(seconds)
        time.sleep(seconds)

    model.sleep = recorded_sleep
    assert model.generate([QUESTION])[0]
    server.kill()  # dies between two requests
    with pytest.raises(EndpointError) as failure:
        model.generate([QUESTION])
    message = str(failure.value)
    assert server.base_url + "/chat/completions" in message and "4 attempts" in message
    assert "refused" in message.lower()
    assert waits == [0.1, 0.2, 0.4], "exponential backoff between the attempts"

    waits.clear()
    server.start()  # not yet listening: the first attempts are refused, a retry reaches it
    patient = _client(server, max_retries=40, backoff=0.25, max_backoff=2.0)
    patient.sleep = recorded_sleep
    assert patient.generate([QUESTION])[0]
    assert waits, "the restarted server was reached by a retry"
    server.wait_ready()


@pytest.mark.slow
def test_generative_planner_runs_one_real_episode(server: LlamaServer) -> None:
    model = _client(server)
    task = load_tasks("benchmark")[0]
    planner = SayCanPlanner(model, SayCanConfig(mode="generative", max_steps=12))
    result = planner.plan(task, PlannerInput(task.instruction))
    skills = {skill.text for skill in vocabulary()}
    assert planner.config.planner_name == "saycan-generative"
    assert result.plan and set(result.plan) <= skills
    assert len(result.generated) == len(result.plan) and all(isinstance(g, str) for g in result.generated)
    assert len(result.trace.steps) >= 1


def test_loglikelihood_is_refused_with_a_pointer_to_the_generative_planner() -> None:
    model = OpenAICompatibleLM("any", base_url="http://127.0.0.1:9")
    assert model.supports_loglikelihood is False
    with pytest.raises(LoglikelihoodUnsupportedError, match="generative planner"):
        model.loglikelihood([LoglikelihoodRequest("a", " b")])
    with pytest.raises(ValueError, match="generative planner"):
        SayCanPlanner(model)


def test_base_url_gets_v1_when_given_a_bare_host() -> None:
    assert OpenAICompatibleLM("m", base_url="http://127.0.0.1:8080").base_url == "http://127.0.0.1:8080/v1"
    assert OpenAICompatibleLM("m", base_url="http://127.0.0.1:8080/v1/").base_url == "http://127.0.0.1:8080/v1"


class _FlakyHandler(http.server.BaseHTTPRequestHandler):
    """Answers 503 a set number of times, then a valid chat completion (unit test of the retry loop)."""

    failures_left = 0
    bodies: list[dict[str, Any]] = []  # noqa: RUF012 - shared on purpose, reset per test

    def do_POST(self) -> None:
        length = int(self.headers["Content-Length"])
        type(self).bodies.append(json.loads(self.rfile.read(length)))
        if type(self).failures_left > 0:
            type(self).failures_left -= 1
            self.send_response(503)
            self.end_headers()
            self.wfile.write(b"overloaded")
            return
        payload = json.dumps({"choices": [{"message": {"role": "assistant", "content": " find a mug, 2. done"}}]})
        self.send_response(200)
        self.send_header("Content-Type", "application/json")
        self.end_headers()
        self.wfile.write(payload.encode())

    def log_message(self, *args: Any) -> None:
        pass


@pytest.fixture
def flaky() -> Iterator[str]:
    _FlakyHandler.failures_left, _FlakyHandler.bodies = 0, []
    httpd = http.server.ThreadingHTTPServer(("127.0.0.1", 0), _FlakyHandler)
    thread = threading.Thread(target=httpd.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{httpd.server_address[1]}/v1"
    finally:
        httpd.shutdown()
        httpd.server_close()
        thread.join(timeout=10)


def test_server_errors_are_retried_with_backoff_and_the_request_is_greedy(flaky: str) -> None:
    _FlakyHandler.failures_left = 2
    model = OpenAICompatibleLM("m", base_url=flaky, api_key="", backoff=0.5, max_backoff=0.75)
    waits: list[float] = []
    model.sleep = waits.append
    request = GenerateRequest("Robot: 1.", max_new_tokens=5, stop=(",", "\n"))
    assert model.generate([request]) == ["find a mug"]
    assert waits == [0.5, 0.75]
    body = _FlakyHandler.bodies[-1]
    assert body["temperature"] == 0.0 and body["max_tokens"] == 5 and body["stop"] == [",", "\n"]
    assert body["messages"] == [{"role": "user", "content": "Robot: 1."}]


def test_persistent_server_errors_end_in_an_error_naming_the_url(flaky: str) -> None:
    _FlakyHandler.failures_left = 10
    model = OpenAICompatibleLM("m", base_url=flaky, max_retries=2, backoff=0.0)
    with pytest.raises(EndpointError, match=r"/v1/chat/completions: no answer after 3 attempts.*HTTP 503"):
        model.generate([QUESTION])
    assert len(_FlakyHandler.bodies) == 3


def test_concurrent_requests_keep_their_order(flaky: str) -> None:
    model = OpenAICompatibleLM("m", base_url=flaky, concurrency=4)
    prompts = [GenerateRequest(f"p{i}", stop=(",",)) for i in range(6)]
    assert model.generate(prompts) == ["find a mug"] * 6
    assert sorted(b["messages"][0]["content"] for b in _FlakyHandler.bodies) == [f"p{i}" for i in range(6)]


def test_local_endpoints_bypass_proxies() -> None:
    # urllib honours *_proxy variables: traffic to a local server must never be sent through one.
    assert OpenAICompatibleLM("m", base_url="http://127.0.0.1:8080")._opener is not None
    assert OpenAICompatibleLM("m", base_url="http://localhost:8080")._opener is not None
    assert OpenAICompatibleLM("m", base_url="https://api.example.org/v1")._opener is None


SCHEMA = '{"type": "object", "properties": {"a": {"type": "string"}}, "required": ["a"]}'


def test_system_messages_and_the_schema_are_sent_as_the_server_wants_them(flaky: str) -> None:
    request = GenerateRequest("Rewrite it.", system="You are a rewriter.", json_schema=SCHEMA)
    OpenAICompatibleLM("m", base_url=flaky).generate([request])
    body = _FlakyHandler.bodies[-1]
    assert body["messages"] == [
        {"role": "system", "content": "You are a rewriter."},
        {"role": "user", "content": "Rewrite it."},
    ]
    assert body["response_format"] == {
        "type": "json_schema",
        "json_schema": {"name": "output", "schema": json.loads(SCHEMA), "strict": True},
    }
    OpenAICompatibleLM("m", base_url=flaky, structured_output="json_object").generate([request])
    assert _FlakyHandler.bodies[-1]["response_format"] == {"type": "json_object", "schema": json.loads(SCHEMA)}
    off = OpenAICompatibleLM("m", base_url=flaky, structured_output="off")
    off.generate([request, GenerateRequest("No schema.")])
    assert off.supports_json_schema is False
    assert all("response_format" not in b for b in _FlakyHandler.bodies[-2:])
    with pytest.raises(ValueError, match="structured_output"):
        OpenAICompatibleLM("m", base_url=flaky, structured_output="xml")  # type: ignore[arg-type]
