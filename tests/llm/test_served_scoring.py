"""SayCan scoring through a server: wire formats (unit tests on answers of the documented shapes) and agreement
with the in-process llama.cpp backend through a real llama-cpp-python server started here on SmolLM2.

llama-cpp-python's server (0.3.x) pairs echoed tokens with the distribution after them for models without a BOS
token (SmolLM2 has none): the real-server test starts it with `tokenizer.ggml.add_bos_token=true` and gives the
client the same BOS rule, and the in-process reference scores the same token ids (BOS first). That the no-BOS
answer is refused is checked on the answer that server gave (its shape recorded below).

No SGLang server installs here: its `/generate` wire format is tested on an answer of the documented shape only.
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
from typing import Any

import pytest

from talkdem.llm.backends.openai_compat import OpenAICompatibleLM
from talkdem.llm.interface.models import FAST_TEST_MODEL, model_path
from talkdem.llm.scoring.served_scoring import ScoringProtocolError, ScoringRequest, read_completions_choice
from talkdem.planner import PlannerInput, SayCanConfig, SayCanPlanner
from talkdem.planner.prompt import append_step
from talkdem.tasks import load_tasks

# Measured on this machine: the server's echoed log-probabilities are float32; the largest difference from the
# in-process float64 scores over the compared candidates was 7.8e-7 nats. A sum of <= 10 float32 terms of size
# <= 25 carries at most ~1.5e-5 of rounding, so 1e-4 separates rounding from a real disagreement (a wrong
# token or position moves a score by whole nats).
TOLERANCE = 1e-4
_NO_PROXY = urllib.request.build_opener(urllib.request.ProxyHandler({}))


def _free_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as probe:
        probe.bind(("127.0.0.1", 0))
        port: int = probe.getsockname()[1]
    return port


# -- a fake vLLM / SGLang for the wire formats -------------------------------------------------------------------
def _fake_logprob(position: int, token: int) -> float:
    return -round(0.25 + (token % 13) * 0.5 + (position % 3) * 0.125, 6)


class _WireHandler(http.server.BaseHTTPRequestHandler):
    """vLLM's `/v1/completions` for token-id prompts (choices answered in reverse order, as a batching server
    may) and SGLang's `/generate`, with deterministic log-probabilities of each (position, token)."""

    bodies: list[dict[str, Any]] = []  # noqa: RUF012 - shared on purpose, reset per test
    drop_generated = False

    def do_POST(self) -> None:
        body = json.loads(self.rfile.read(int(self.headers["Content-Length"])))
        type(self).bodies.append(body)
        if self.path == "/v1/completions":
            choices = []
            for index, ids in enumerate(body["prompt"]):
                echoed = [*ids, 7] if not type(self).drop_generated else ids
                values = [None, *[_fake_logprob(p, t) for p, t in enumerate(echoed)][1:]]
                tokens = [f"token_id:{t}" for t in echoed]
                offsets = list(range(len(echoed)))
                logprobs = {"tokens": tokens, "token_logprobs": values, "text_offset": offsets, "top_logprobs": []}
                choices.append({"index": index, "text": "", "logprobs": logprobs, "finish_reason": "length"})
            answer: Any = {"object": "text_completion", "choices": choices[::-1]}
        elif self.path == "/generate":
            start = body["logprob_start_len"]
            answer = [
                {
                    "text": "",
                    "meta_info": {
                        "prompt_tokens": len(ids),
                        "completion_tokens": 0,
                        "input_token_logprobs": [
                            [_fake_logprob(p, ids[p]), ids[p], None] for p in range(start, len(ids))
                        ],
                        "output_token_logprobs": [],
                    },
                }
                for ids in body["input_ids"]
            ]
        else:
            self.send_response(404)
            self.end_headers()
            return
        payload = json.dumps(answer).encode()
        self.send_response(200)
        self.send_header("Content-Type", "application/json")
        self.end_headers()
        self.wfile.write(payload)

    def log_message(self, *args: Any) -> None:
        pass


@pytest.fixture
def wire() -> Iterator[str]:
    _WireHandler.bodies, _WireHandler.drop_generated = [], False
    httpd = http.server.ThreadingHTTPServer(("127.0.0.1", 0), _WireHandler)
    thread = threading.Thread(target=httpd.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{httpd.server_address[1]}/v1"
    finally:
        httpd.shutdown()
        httpd.server_close()
        thread.join(timeout=10)


def _expected(model: OpenAICompatibleLM, context: str, continuation: str) -> float:
    assert model.tokenizer is not None
    n = len(model.tokenizer.context_ids(context))
    ids = model.tokenizer.encode(continuation)
    return sum(_fake_logprob(n + j, t) for j, t in enumerate(ids))


CONTEXT = "Robot: Hi there.\nHuman pending instruction: put the apple in the fridge.\nRobot: 1."
CANDIDATES = [" find an apple", " find a fridge", " pick up the apple", " done"]


def test_vllm_token_id_prompts_one_request_per_step_sum_by_token_count(wire: str) -> None:
    model = OpenAICompatibleLM("m", base_url=wire, tokenizer=FAST_TEST_MODEL)
    assert model.supports_loglikelihood
    scores = model.score_continuations(CONTEXT, CANDIDATES)
    assert len(_WireHandler.bodies) == 1, "all candidates of a step in one request"
    body = _WireHandler.bodies[0]
    assert body["echo"] is True and body["logprobs"] == 1 and body["max_tokens"] == 1
    assert model.tokenizer is not None
    context_ids = model.tokenizer.context_ids(CONTEXT)
    assert body["prompt"] == [context_ids + model.tokenizer.encode(c) for c in CANDIDATES]
    # choices came back in reverse order: matched by index, summed over the continuation's tokens only
    assert scores == pytest.approx([_expected(model, CONTEXT, c) for c in CANDIDATES], abs=1e-9)
    header_info = model.run_info()
    assert header_info["tokenizer"] == FAST_TEST_MODEL and header_info["scoring_api"] == "completions"
    assert model.identity.revision.startswith(f"tokenizer {FAST_TEST_MODEL} ")


def test_planner_scores_through_the_served_backend_without_a_special_case(wire: str) -> None:
    model = OpenAICompatibleLM("m", base_url=wire, tokenizer=FAST_TEST_MODEL)
    task = load_tasks("benchmark")[0]
    result = SayCanPlanner(model, SayCanConfig(max_steps=3)).plan(task, PlannerInput(task.instruction))
    assert len(result.plan) >= 1 and len(_WireHandler.bodies) == len(result.plan), "one request per step"
    assert all(len(body["prompt"]) >= 200 for body in _WireHandler.bodies)


def test_an_answer_without_the_generated_token_is_refused(wire: str) -> None:
    _WireHandler.drop_generated = True
    model = OpenAICompatibleLM("m", base_url=wire, tokenizer=FAST_TEST_MODEL)
    with pytest.raises(ScoringProtocolError, match="without a BOS token"):
        model.score_continuations(CONTEXT, CANDIDATES)


def test_sglang_generate_wire_format(wire: str) -> None:
    model = OpenAICompatibleLM("m", base_url=wire, tokenizer=FAST_TEST_MODEL, scoring_api="sglang")
    scores = model.score_continuations(CONTEXT, CANDIDATES)
    (body,) = _WireHandler.bodies
    assert model.tokenizer is not None
    assert body["logprob_start_len"] == len(model.tokenizer.context_ids(CONTEXT))
    assert body["sampling_params"]["max_new_tokens"] == 0 and body["return_logprob"] is True
    assert scores == pytest.approx([_expected(model, CONTEXT, c) for c in CANDIDATES], abs=1e-9)


# The answer llama-cpp-python 0.3.36's server gave for "Robot: 1. find an apple" on SmolLM2 (no BOS token): nine
# entries for nine prompt tokens, each paired with the distribution after it, and none for the generated token.
_RECORDED_NO_BOS = {
    "index": 0,
    "logprobs": {
        "tokens": ["Rob", "ot", ":", " ", "1", ".", " find", " an", " apple"],
        "token_logprobs": [None, -8.736, -11.413, -8.989, -2.227, -13.400, -9.383, -7.793, -8.021],
        "text_offset": [0, 3, 5, 6, 7, 8, 9, 14, 17],
    },
}


def test_llama_cpp_python_no_bos_misalignment_is_refused_not_scored() -> None:
    request = ScoringRequest((20348, 320, 42, 216, 33, 30), (1042, 354, 11977), "", " find an apple", False)
    with pytest.raises(ScoringProtocolError, match="9 echoed entries for 9 prompt tokens"):
        read_completions_choice(_RECORDED_NO_BOS, request, lambda t: b"", "recorded")


def test_sum_by_token_count_not_text_offset() -> None:
    # A BOS model's answer from llama-cpp-python: BOS not echoed, generated token last; offsets are decoded
    # lengths (here deliberately not positions in the prompt string) and must not matter.
    request = ScoringRequest((1, 5, 6), (8, 9), "", " x y", True)
    choice = {
        "index": 0,
        "logprobs": {
            "tokens": ["a", "b", " x", " y", "!"],
            "token_logprobs": [None, -1.0, -2.0, -3.0, -0.5],
            "text_offset": [0, 0, 0, 0, 0],
        },
    }
    assert read_completions_choice(choice, request, {8: b" x", 9: b" y"}.__getitem__, "t") == -5.0
    wrong = {**choice, "logprobs": {**choice["logprobs"], "tokens": ["a", "b", " x", " z", "!"]}}
    with pytest.raises(ScoringProtocolError, match="not ours"):
        read_completions_choice(wrong, request, {8: b" x", 9: b" y"}.__getitem__, "t")


# -- a real llama-cpp-python server ----------------------------------------------------------------------------
@pytest.fixture(scope="module")
def bos_server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    port = _free_port()
    log = tmp_path_factory.mktemp("served") / "server.log"
    command = [sys.executable, "-m", "llama_cpp.server", "--model", str(model_path(FAST_TEST_MODEL))]
    command += ["--model_alias", "smollm2", "--host", "127.0.0.1", "--port", str(port), "--n_ctx", "4096"]
    # logits_all keeps every position's logits (its default, stated so a changed default cannot hide);
    # float32 keys/values as the in-process backend; BOS on, so that its echo is aligned (see the docstring).
    command += ["--n_threads", "2", "--logits_all", "True", "--type_k", "0", "--type_v", "0", "--verbose", "False"]
    command += ["--kv_overrides", "tokenizer.ggml.add_bos_token=bool:true"]
    with log.open("ab") as handle:
        process = subprocess.Popen(command, stdout=handle, stderr=subprocess.STDOUT)
    base_url = f"http://127.0.0.1:{port}/v1"
    try:
        deadline = time.monotonic() + 120
        while True:
            if process.poll() is not None or time.monotonic() > deadline:
                raise RuntimeError(f"the server did not start: {log.read_text()[-2000:]}")
            try:
                with _NO_PROXY.open(base_url + "/models", timeout=5):
                    break
            except OSError:
                time.sleep(0.5)
        yield base_url
    finally:
        process.terminate()
        try:
            process.wait(timeout=15)
        except subprocess.TimeoutExpired:
            process.kill()


@pytest.mark.slow
def test_real_server_scores_agree_with_in_process_llamacpp_over_saycan_steps(bos_server: str) -> None:
    from talkdem.llm.backends.llamacpp import LlamaCppLM

    local = LlamaCppLM(FAST_TEST_MODEL, threads=2)
    served = OpenAICompatibleLM(
        "smollm2", base_url=bos_server, tokenizer=FAST_TEST_MODEL, prompt_format="text", add_bos=True, timeout=600
    )
    assert served.tokenizer is not None
    task = load_tasks("benchmark")[0]
    # The zero-shot SayCan prompt (header + instruction, ~70 tokens): this server post-processes every echoed
    # position in Python (a sort of the vocabulary each), about 0.1 s a token here, so the few-shot prompt's
    # 630 tokens would take a minute per candidate.
    planner = SayCanPlanner(local, examples=())
    context = planner.prompt_for(PlannerInput(task.instruction))
    for step in (1, 2):
        context_ids = served.tokenizer.context_ids(context)
        continuations = [" " + skill for skill in planner.skills]
        full = local.score_token_continuations(context_ids, [served.tokenizer.encode(c) for c in continuations])
        ranked = sorted(range(len(full)), key=lambda i: (-full[i], i))
        compared = [ranked[0], ranked[1], ranked[2], ranked[100]]
        scores = served.score_continuations(context, [continuations[i] for i in compared])
        assert scores == pytest.approx([full[i] for i in compared], abs=TOLERANCE)
        assert max(range(len(compared)), key=lambda k: scores[k]) == 0, "the same choice as in process"
        context = append_step(context, planner.skills[ranked[0]], step + 1)
