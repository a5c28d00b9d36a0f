"""A stand-in vLLM for run tests: `/v1/completions` with token-id prompts, echo and logprobs, on 127.0.0.1.

It tokenizes nothing and loads no weights: prompts are decoded with the test model's GGUF vocabulary, the
step's context is the prompts' common prefix, and the candidate the scripted test model prefers gets the
highest summed log-probability (spread over its tokens). Used where a real server would add nothing but
time: runs through the served client with concurrency, shards, a killed server and resume.

    python wire_server.py PORT LOG [DELAY_SECONDS]

Each request is logged as one JSON line: the episode's instruction line and the number of prompts.
"""

from __future__ import annotations

import http.server
import json
import sys
import time
from pathlib import Path
from typing import Any

from llama_cpp import Llama

from talkdem.llm.interface.models import FAST_TEST_MODEL, model_path

SCRIPT = ["find an apple", "pick up the apple", "done"]
VOCAB: Any = None
LOG = Path(".")
DELAY = 0.0


def _text(ids: list[int]) -> str:
    return bytes(VOCAB.detokenize(ids)).decode("utf-8", errors="replace")


def _wanted(context: str) -> str:
    steps_taken = context.rsplit("Robot: 1.", 1)[-1].count(",")
    return SCRIPT[min(steps_taken, len(SCRIPT) - 1)]


def _common(prompts: list[list[int]]) -> int:
    n = min(len(p) for p in prompts)
    for k in range(n):
        if any(p[k] != prompts[0][k] for p in prompts):
            return k
    return n


class Handler(http.server.BaseHTTPRequestHandler):
    def do_POST(self) -> None:
        body = json.loads(self.rfile.read(int(self.headers["Content-Length"])))
        time.sleep(DELAY)
        prompts: list[list[int]] = body["prompt"]
        start = _common(prompts) if len(prompts) > 1 else len(prompts[0]) - 1
        context = _text(prompts[0][:start])
        wanted = _wanted(context)
        choices = []
        for index, ids in enumerate(prompts):
            continuation = _text(ids[start:])
            score = 0.0 if continuation.strip() == wanted else -10.0 - len(continuation)
            values: list[float | None] = [None] + [0.0] * (len(ids) - 1) + [-0.5]
            values[-2] = score
            tokens = [""] * start + [_text([t]) for t in ids[start:]] + ["!"]  # the client reads the continuation
            logprobs = {"tokens": tokens, "token_logprobs": values, "text_offset": [0] * len(tokens)}
            choices.append({"index": index, "text": "", "logprobs": logprobs, "finish_reason": "length"})
        instruction = next((line for line in context.splitlines()[::-1] if line.startswith("Human")), "")
        with LOG.open("a") as log:
            log.write(json.dumps({"instruction": instruction, "prompts": len(prompts)}) + "\n")
        payload = json.dumps({"object": "text_completion", "choices": choices[::-1]}).encode()
        self.send_response(200)
        self.send_header("Content-Type", "application/json")
        self.end_headers()
        self.wfile.write(payload)

    def do_GET(self) -> None:
        payload = b'{"data": []}'
        self.send_response(200)
        self.end_headers()
        self.wfile.write(payload)

    def log_message(self, *args: Any) -> None:
        pass


if __name__ == "__main__":
    port, LOG = int(sys.argv[1]), Path(sys.argv[2])
    DELAY = float(sys.argv[3]) if len(sys.argv) > 3 else 0.0
    VOCAB = Llama(model_path=str(model_path(FAST_TEST_MODEL)), vocab_only=True, verbose=False)
    http.server.ThreadingHTTPServer(("127.0.0.1", port), Handler).serve_forever()
