"""Answers a server may give that no model can: a log-probability above 0 (a probability above 1) or
infinite is refused with one line naming the server and the token, never summed into a SayCan score; an
answer that is not UTF-8 is refused naming the URL. Float32 rounding just above 0 is counted as 0."""

from __future__ import annotations

import http.server
import json
import threading
from collections.abc import Iterator
from typing import Any

import pytest

from talkdem.llm.scoring.served_scoring import (
    ScoringProtocolError,
    ScoringRequest,
    read_completions_choice,
    read_sglang_item,
)

# A BOS model's echo (BOS not echoed, the generated token last), as in test_served_scoring.
REQUEST = ScoringRequest((1, 5, 6), (8, 9), "", " x y", True)
PIECES = {8: b" x", 9: b" y"}.__getitem__


def _choice(values: list[Any]) -> dict[str, Any]:
    return {"index": 0, "logprobs": {"tokens": ["a", "b", " x", " y", "!"], "token_logprobs": [None, *values]}}


@pytest.mark.parametrize(
    ("value", "message"),
    [
        (0.7, "at most 0"),
        (float("inf"), "must be finite"),
        (float("-inf"), "must be finite"),
        (float("nan"), "not a number"),
        ("-1.0", "not a number"),
    ],
)
def test_impossible_log_probabilities_are_refused(value: Any, message: str) -> None:
    with pytest.raises(ScoringProtocolError, match=message) as refused:
        read_completions_choice(_choice([-1.0, -2.0, value, -0.5]), REQUEST, PIECES, "http://server/v1/completions")
    assert "http://server/v1/completions" in str(refused.value) and "token 3" in str(refused.value)
    item = {"meta_info": {"input_token_logprobs": [[-1.0, 8, None], [value, 9, None]]}}
    with pytest.raises(ScoringProtocolError, match=message):
        read_sglang_item(item, REQUEST, "http://server/generate")


def test_float_rounding_just_above_zero_counts_as_zero() -> None:
    # float32 log-softmax of a near-certain token: 0 up to rounding. It must not raise a skill's sum above
    # the partial sums branch and bound relies on.
    assert read_completions_choice(_choice([-1.0, -2.0, 3e-7, -0.5]), REQUEST, PIECES, "t") == -2.0
    item = {"meta_info": {"input_token_logprobs": [[2e-6, 8, None], [-1.5, 9, None]]}}
    assert read_sglang_item(item, REQUEST, "t") == -1.5


class _Latin1(http.server.BaseHTTPRequestHandler):
    def do_POST(self) -> None:
        self.rfile.read(int(self.headers["Content-Length"]))
        payload = '{"choices": [{"message": {"content": "caf\u00e9"}}]}'.encode("latin-1")
        self.send_response(200)
        self.send_header("Content-Type", "application/json")
        self.end_headers()
        self.wfile.write(payload)

    def log_message(self, *args: Any) -> None:
        pass


@pytest.fixture
def latin1_server() -> Iterator[str]:
    httpd = http.server.ThreadingHTTPServer(("127.0.0.1", 0), _Latin1)
    thread = threading.Thread(target=httpd.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{httpd.server_address[1]}/v1"
    finally:
        httpd.shutdown()
        httpd.server_close()
        thread.join(timeout=10)


def test_an_answer_that_is_not_utf8_names_the_url(latin1_server: str) -> None:
    from talkdem.llm.backends.openai_compat import EndpointError, OpenAICompatibleLM
    from talkdem.llm.interface.requests import GenerateRequest

    model = OpenAICompatibleLM("m", base_url=latin1_server, max_retries=1, backoff=0)
    with pytest.raises(EndpointError) as refused:
        model.generate([GenerateRequest("hello", max_new_tokens=4)])
    assert latin1_server in str(refused.value) and "not UTF-8" in str(refused.value)
    json.dumps(str(refused.value))  # one printable line
    assert "\n" not in str(refused.value)
