"""Served SayCan scoring against in-process scoring, on SmolLM2-135M (2 threads), side by side.

Measured on a stratified benchmark task's few-shot SayCan prompt (the 214 skills of one step):
- in process (llama.cpp): the exact branch-and-bound choice, and every skill scored (full trie);
- llama-cpp-python's OpenAI-compatible server (`/v1/completions`, echo, one string per request, started with a
  BOS token so that its echo is aligned): seconds per candidate request, on the zero-shot prompt (~70 tokens)
  and on the few-shot prompt; a step is 214 such requests, so its cost is extrapolated (printed as such);
- the client's own work for one step of a token-id server (vLLM, SGLang): tokenizing the step, encoding the
  request and reading an answer of 214 echoed prompts (no server time).
The load average is printed because the machine may be shared.
"""

from __future__ import annotations

import json
import os
import socket
import subprocess
import sys
import time
import urllib.request

THREADS = 2


def _free_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as probe:
        probe.bind(("127.0.0.1", 0))
        port: int = probe.getsockname()[1]
    return port


def _wait(url: str, process: subprocess.Popen[bytes]) -> None:
    opener = urllib.request.build_opener(urllib.request.ProxyHandler({}))
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and process.poll() is None:
        try:
            with opener.open(url + "/models", timeout=5):
                return
        except OSError:
            time.sleep(0.5)
    raise RuntimeError("the llama-cpp-python server did not start")


def main() -> None:
    try:
        from talkdem.llm.backends.llamacpp import LlamaCppLM
    except ImportError as error:
        print(f"served scoring: skipped ({error})")
        return
    from talkdem.llm.backends.openai_compat import OpenAICompatibleLM
    from talkdem.llm.interface.models import FAST_TEST_MODEL, model_path
    from talkdem.llm.scoring.served_scoring import ScoringRequest, completions_body, read_completions_choice
    from talkdem.planner import PlannerInput, SayCanPlanner
    from talkdem.tasks import load_tasks

    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} CPUs")
    local = LlamaCppLM(FAST_TEST_MODEL, threads=THREADS)
    task = load_tasks("benchmark")[0]
    planner = SayCanPlanner(local)
    few_shot = planner.prompt_for(PlannerInput(task.instruction))
    zero_shot = SayCanPlanner(local, examples=()).prompt_for(PlannerInput(task.instruction))
    continuations = [" " + skill for skill in planner.skills]

    port = _free_port()
    command = [sys.executable, "-m", "llama_cpp.server", "--model", str(model_path(FAST_TEST_MODEL))]
    command += ["--model_alias", "smollm2", "--host", "127.0.0.1", "--port", str(port), "--n_ctx", "4096"]
    command += ["--n_threads", str(THREADS), "--type_k", "0", "--type_v", "0", "--verbose", "False"]
    command += ["--kv_overrides", "tokenizer.ggml.add_bos_token=bool:true"]
    server = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        url = f"http://127.0.0.1:{port}/v1"
        _wait(url, server)
        served = OpenAICompatibleLM(
            "smollm2", base_url=url, tokenizer=FAST_TEST_MODEL, prompt_format="text", add_bos=True, timeout=900
        )
        tokenizer = served.tokenizer
        assert tokenizer is not None
        ids = [tokenizer.encode(c) for c in continuations]
        for name, context in (("zero-shot", zero_shot), ("few-shot", few_shot)):
            context_ids = tokenizer.context_ids(context)
            local.forget_context()
            start = time.perf_counter()
            local.best_token_continuation(context_ids, ids)
            cold_bb = time.perf_counter() - start
            start = time.perf_counter()
            local.score_token_continuations(context_ids, ids)
            full = time.perf_counter() - start
            start = time.perf_counter()
            served.score_continuations(context, continuations[:1])
            per_request = time.perf_counter() - start
            print(
                f"{name} prompt ({len(context_ids)} tokens): in process {cold_bb:.2f} s a step (branch and bound, "
                f"prompt cold), {full:.2f} s (all 214 skills, prompt cached); llama-cpp-python server "
                f"{per_request:.1f} s per candidate request -> about {per_request * 214 / 60:.0f} min a step "
                f"(extrapolated: 214 requests), {per_request * 214 / full:.0f}x the in-process full scoring"
            )
    finally:
        server.terminate()
        server.wait(timeout=30)

    # The client's own work for one step against a token-id server (vLLM/SGLang): no server time.
    model = OpenAICompatibleLM("m", base_url="http://127.0.0.1:9", tokenizer=FAST_TEST_MODEL)
    assert model.tokenizer is not None
    start = time.perf_counter()
    step_ids = tuple(model.tokenizer.context_ids(few_shot))
    requests = [ScoringRequest(step_ids, tuple(model.tokenizer.encode(c))) for c in continuations]
    body = json.dumps(completions_body("m", requests, "ids"))
    build = time.perf_counter() - start
    answers = []
    for request in requests:
        tokens = [""] * len(step_ids) + [model.tokenizer.piece(t).decode() for t in request.continuation_ids]
        values = [None, *[-0.1] * (len(request.ids) - 1), -0.1]
        answers.append({"index": 0, "logprobs": {"tokens": [*tokens, "x"], "token_logprobs": values}})
    answer_text = json.dumps({"choices": answers})
    start = time.perf_counter()
    for choice, request in zip(json.loads(answer_text)["choices"], requests, strict=True):
        read_completions_choice(choice, request, model.tokenizer.piece, "bench")
    read = time.perf_counter() - start
    print(
        f"token-id client, one step: {build:.2f} s to tokenize and encode ({len(body) / 1e6:.1f} MB request), "
        f"{read:.3f} s to read 214 echoed prompts"
    )


if __name__ == "__main__":
    main()
