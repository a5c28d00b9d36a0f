"""Any OpenAI-compatible endpoint (a vLLM server, llama.cpp's server, a hosted API), standard library only.

Chat endpoints give no prompt log-likelihoods, so this backend only generates: it serves CoT/TOCC
rewriting, the dataset's LLM generators, and the generative SayCan planner (`SayCanConfig(mode="generative")`,
labelled `saycan-generative` in results). `loglikelihood` raises `LoglikelihoodUnsupportedError`.

Server errors (5xx, 429), refused or dropped connections and timeouts are retried with exponential
backoff; once the retries are spent, `EndpointError` names the URL and the last failure. Client errors
(4xx) are not retried: retrying a bad request cannot help.
"""

from __future__ import annotations

import http.client
import json
import os
import time
import urllib.error
import urllib.parse
import urllib.request
from collections.abc import Callable, Sequence
from concurrent.futures import ThreadPoolExecutor
from typing import Any, Literal

from talkdem.llm.base import LanguageModel, ModelIdentity, cut_at_stop
from talkdem.llm.requests import GenerateRequest, LoglikelihoodRequest

__all__ = ["API_KEY_ENV", "EndpointError", "LoglikelihoodUnsupportedError", "OpenAICompatibleLM"]

API_KEY_ENV = "OPENAI_API_KEY"
_MAX_STOP_STRINGS = 4  # the OpenAI API accepts at most four; the rest are applied locally by `cut_at_stop`

Endpoint = Literal["chat", "completions", "auto"]


class EndpointError(RuntimeError):
    """The endpoint could not answer: retries spent on server errors or timeouts, or a client error."""


class LoglikelihoodUnsupportedError(NotImplementedError):
    """Chat endpoints return no log-probabilities of prompt tokens."""


class _Retryable(Exception):
    """A failure worth another attempt (server error, rate limit, connection problem, timeout)."""

    def __init__(self, reason: str, retry_after: float | None = None) -> None:
        super().__init__(reason)
        self.retry_after = retry_after


def _normalize_base_url(base_url: str) -> str:
    """`http://host:8000` and `http://host:8000/v1/` both mean `http://host:8000/v1`."""
    url = base_url.rstrip("/")
    if not urllib.parse.urlsplit(url).path:
        url += "/v1"
    return url


class OpenAICompatibleLM(LanguageModel):
    """Generation through `/v1/chat/completions` (default) or `/v1/completions`; greedy unless asked to sample.

    Args:
        model: the served model name (vLLM: `--served-model-name`; llama.cpp's server accepts any name).
        base_url: as OpenAI's client takes it, e.g. `http://127.0.0.1:8000/v1` (a bare host gets `/v1`).
        api_key: sent as a bearer token; defaults to `$OPENAI_API_KEY`; none is sent when both are empty.
        timeout: seconds for connecting and for each read of one HTTP request.
        max_retries: further attempts after the first, on server errors, connection errors and timeouts.
        backoff: the first wait between attempts in seconds, doubled after each retry up to `max_backoff`.
        endpoint: `chat`, `completions` (raw text continuation, for base models), or `auto` (chat, falling back
            to completions for good when the server has no chat route or no chat template).
        concurrency: requests of one batch sent in parallel (hosted APIs); 1 sends them one after another.
    """

    supports_loglikelihood = False

    def __init__(
        self,
        model: str,
        base_url: str = "http://127.0.0.1:8000/v1",
        api_key: str | None = None,
        timeout: float = 60.0,
        max_retries: int = 5,
        backoff: float = 0.5,
        max_backoff: float = 8.0,
        endpoint: Endpoint = "chat",
        concurrency: int = 1,
    ) -> None:
        if max_retries < 0 or timeout <= 0 or backoff < 0 or concurrency < 1:
            raise ValueError("need max_retries >= 0, timeout > 0, backoff >= 0 and concurrency >= 1")
        if endpoint not in ("chat", "completions", "auto"):
            raise ValueError(f"endpoint must be 'chat', 'completions' or 'auto', got {endpoint!r}")
        self.model = model
        self.base_url = _normalize_base_url(base_url)
        self.api_key = api_key if api_key is not None else os.environ.get(API_KEY_ENV) or None
        self.timeout = timeout
        self.max_retries = max_retries
        self.backoff = backoff
        self.max_backoff = max_backoff
        self.endpoint: Endpoint = endpoint
        self.concurrency = concurrency
        self.sleep: Callable[[float], None] = time.sleep
        self.identity = ModelIdentity(backend="openai", name=model, revision=self.base_url)
        # A server on this machine is never reached through a proxy named in *_proxy variables.
        local = urllib.parse.urlsplit(self.base_url).hostname in ("127.0.0.1", "localhost", "::1")
        self._opener = urllib.request.build_opener(urllib.request.ProxyHandler({})) if local else None

    # -- the interface --------------------------------------------------------------------------------
    def loglikelihood(self, requests: Sequence[LoglikelihoodRequest]) -> list[float]:
        raise LoglikelihoodUnsupportedError(
            f"{self.identity.key()}: an OpenAI-compatible chat endpoint gives no prompt log-likelihoods; "
            "use the generative planner (SayCanConfig(mode='generative'), `talkdem run --planner generative`) "
            "or a local backend (hf, llamacpp, vllm) for scoring"
        )

    def generate(self, requests: Sequence[GenerateRequest]) -> list[str]:
        if self.concurrency == 1 or len(requests) <= 1:
            return [self._generate_one(request) for request in requests]
        with ThreadPoolExecutor(max_workers=self.concurrency) as pool:
            return list(pool.map(self._generate_one, requests))

    # -- one request ----------------------------------------------------------------------------------
    def _generate_one(self, request: GenerateRequest) -> str:
        if self.endpoint in ("chat", "auto"):
            try:
                text = self._chat(request)
            except EndpointError as error:
                if self.endpoint != "auto" or not _no_chat_support(error):
                    raise
                self.endpoint = "completions"
                text = self._completion(request)
        else:
            text = self._completion(request)
        return cut_at_stop(text, request.stop).strip()

    def _common_fields(self, request: GenerateRequest) -> dict[str, Any]:
        fields: dict[str, Any] = {
            "model": self.model,
            "max_tokens": request.max_new_tokens,
            "temperature": request.temperature,
        }
        if request.temperature > 0:
            fields["seed"] = request.seed  # honoured by vLLM and llama.cpp servers; best effort elsewhere
        stop = [marker for marker in request.stop if marker][:_MAX_STOP_STRINGS]
        if stop:
            fields["stop"] = stop
        return fields

    def _chat(self, request: GenerateRequest) -> str:
        body = {**self._common_fields(request), "messages": [{"role": "user", "content": request.prompt}]}
        choice = self._first_choice(self._post("/chat/completions", body))
        message = choice.get("message") or {}
        return str(message.get("content") or "")

    def _completion(self, request: GenerateRequest) -> str:
        body = {**self._common_fields(request), "prompt": request.prompt}
        return str(self._first_choice(self._post("/completions", body)).get("text") or "")

    def _first_choice(self, response: dict[str, Any]) -> dict[str, Any]:
        choices = response.get("choices")
        if not isinstance(choices, list) or not choices or not isinstance(choices[0], dict):
            raise EndpointError(f"{self.base_url}: a response without choices: {json.dumps(response)[:300]}")
        first: dict[str, Any] = choices[0]
        return first

    def _post(self, route: str, body: dict[str, Any]) -> dict[str, Any]:
        """POST JSON with retries; the parsed JSON answer."""
        url = self.base_url + route
        payload = json.dumps(body).encode()
        headers = {"Content-Type": "application/json", "Accept": "application/json"}
        if self.api_key:
            headers["Authorization"] = f"Bearer {self.api_key}"
        last_failure, retry_after = "", 0.0
        for attempt in range(self.max_retries + 1):
            if attempt:
                self.sleep(min(max(self.backoff * 2 ** (attempt - 1), retry_after), self.max_backoff))
            try:
                return self._post_once(url, payload, headers)
            except _Retryable as failure:
                last_failure, retry_after = str(failure), failure.retry_after or 0.0
        raise EndpointError(
            f"{url}: no answer after {self.max_retries + 1} attempts (backoff from {self.backoff} s); "
            f"last failure: {last_failure}"
        )

    def _post_once(self, url: str, payload: bytes, headers: dict[str, str]) -> dict[str, Any]:
        http_request = urllib.request.Request(url, data=payload, headers=headers, method="POST")
        try:
            opened = (self._opener.open if self._opener else urllib.request.urlopen)(http_request, timeout=self.timeout)
            with opened as response:
                raw = response.read()
        except urllib.error.HTTPError as error:
            detail = error.read().decode(errors="replace")[:500]
            reason = f"HTTP {error.code} {error.reason}: {detail}"
            if error.code >= 500 or error.code == 429:
                raise _Retryable(reason, _retry_after(error.headers.get("Retry-After"))) from error
            raise EndpointError(f"{url}: {reason}") from error
        except urllib.error.URLError as error:
            raise _Retryable(f"{type(error.reason).__name__}: {error.reason}") from error
        except TimeoutError as error:  # socket.timeout is an alias
            raise _Retryable(f"timed out after {self.timeout} s") from error
        except (ConnectionError, http.client.HTTPException) as error:
            raise _Retryable(f"{type(error).__name__}: {error}") from error
        try:
            parsed = json.loads(raw)
        except json.JSONDecodeError as error:
            raise _Retryable(f"an answer that is not JSON: {raw[:200]!r}") from error
        if not isinstance(parsed, dict):
            raise EndpointError(f"{url}: expected a JSON object, got {raw[:200]!r}")
        return parsed


def _retry_after(value: str | None) -> float | None:
    try:
        return max(0.0, float(value)) if value else None
    except ValueError:
        return None  # an HTTP date: fall back to our own backoff


def _no_chat_support(error: EndpointError) -> bool:
    """A client error saying the server has no chat route or the model has no chat template."""
    text = str(error).lower()
    return "http 404" in text or ("http 400" in text and "template" in text) or "http 405" in text
