"""Any OpenAI-compatible endpoint (a vLLM server, llama.cpp's server, a hosted API), standard library only.

Generation serves CoT/TOCC rewriting, the dataset's LLM generators and the generative SayCan planner
(`SayCanConfig(mode="generative")`, labelled `saycan-generative` in results). Chat endpoints give no prompt
log-likelihoods; given the served model's own `tokenizer` (a GGUF file, a catalog name or a local Hugging Face
tokenizer folder), this backend also scores: SayCan's log-likelihood protocol over `/v1/completions` with echoed
prompt log-probabilities (vLLM: token-id prompts, all candidates of a step in one request; llama-cpp-python's
server: one string per request) or SGLang's `/generate` (see `talkdem.llm.scoring.served_scoring`). Without a tokenizer
`loglikelihood` raises `LoglikelihoodUnsupportedError`.

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
from typing import Any, ClassVar, Literal

from talkdem.llm.interface.base import LanguageModel, ModelIdentity, cut_at_stop, loglikelihood_by_context
from talkdem.llm.interface.options import BackendOption
from talkdem.llm.interface.requests import GenerateRequest, LoglikelihoodRequest
from talkdem.llm.scoring.served_scoring import (
    PromptFormat,
    ScoringProtocolError,
    ScoringRequest,
    completions_body,
    read_completions_choice,
    read_sglang_item,
    sglang_body,
)

__all__ = [
    "API_KEY_ENV",
    "STRUCTURED_OUTPUTS",
    "EndpointError",
    "LoglikelihoodUnsupportedError",
    "OpenAICompatibleLM",
    "ScoringAPI",
    "StructuredOutput",
]

API_KEY_ENV = "OPENAI_API_KEY"
_MAX_STOP_STRINGS = 4  # the OpenAI API accepts at most four; the rest are applied locally by `cut_at_stop`

Endpoint = Literal["chat", "completions", "auto"]
ScoringAPI = Literal["completions", "sglang"]
StructuredOutput = Literal["json_schema", "json_object", "off"]
STRUCTURED_OUTPUTS: tuple[StructuredOutput, ...] = ("json_schema", "json_object", "off")


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
        tokenizer: the served model's tokenizer (GGUF file, catalog name or local HF tokenizer folder): enables
            log-likelihood scoring, split exactly as the in-process backends split.
        scoring_api: `completions` (echoed prompt log-probabilities) or `sglang` (native `/generate`).
        prompt_format: `ids` (token-id prompts, one request per step: vLLM) or `text` (one string per request,
            tokenized by the server and checked through `/extras/tokenize`: llama-cpp-python's server).
        add_bos: override the tokenizer's BOS rule (for a server started with another rule).
        structured_output: how a request's JSON schema is sent as `response_format`: `json_schema` (OpenAI's form,
            vLLM's and llama.cpp's `llama-server`), `json_object` with a `schema` field (llama-cpp-python's server),
            or `off` for servers that constrain nothing (the schema is then not sent; output is free text).
    """

    supports_loglikelihood = False
    # Not settable by name: `base_url` (the run spreads its episodes over `--base-url` servers, one client each),
    # `api_key` (a secret: from $OPENAI_API_KEY, never on a command line or in a header) and `concurrency` (its
    # name is the run's `--concurrency`, episodes stepping at once; one client's parallel requests are a caller's).
    options: ClassVar[tuple[BackendOption, ...]] = (
        BackendOption("timeout", "float", "seconds to wait for one answer", minimum=0, above_minimum=True),
        BackendOption("max_retries", "int", "further attempts after a server error or timeout", minimum=0),
        BackendOption("backoff", "float", "first wait between attempts (seconds), doubled each retry", minimum=0),
        BackendOption("max_backoff", "float", "longest wait between attempts (seconds)", minimum=0),
        BackendOption(
            "endpoint", "choice", "generation route", choices={e: e for e in ("chat", "completions", "auto")}
        ),
        BackendOption("tokenizer", "str", "the served model's tokenizer (model name, GGUF file or HF folder)"),
        BackendOption("scoring_api", "choice", "scoring route", choices={a: a for a in ("completions", "sglang")}),
        BackendOption("prompt_format", "choice", "scoring prompts as", choices={f: f for f in ("ids", "text")}),
        BackendOption(
            "add_bos", "choice", "the tokenizer's BOS rule", choices={"model": None, "always": True, "never": False}
        ),
        BackendOption(
            "structured_output", "choice", "how a JSON schema is sent", choices={s: s for s in STRUCTURED_OUTPUTS}
        ),
    )

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
        tokenizer: str | None = None,
        scoring_api: ScoringAPI = "completions",
        prompt_format: PromptFormat = "ids",
        add_bos: bool | None = None,
        structured_output: StructuredOutput = "json_schema",
    ) -> None:
        if structured_output not in STRUCTURED_OUTPUTS:
            raise ValueError(
                f"structured_output must be one of {', '.join(STRUCTURED_OUTPUTS)}, got {structured_output!r}"
            )
        if max_retries < 0 or timeout <= 0 or backoff < 0 or concurrency < 1:
            raise ValueError("need max_retries >= 0, timeout > 0, backoff >= 0 and concurrency >= 1")
        if endpoint not in ("chat", "completions", "auto"):
            raise ValueError(f"endpoint must be 'chat', 'completions' or 'auto', got {endpoint!r}")
        if scoring_api not in ("completions", "sglang") or prompt_format not in ("ids", "text"):
            raise ValueError("scoring_api must be 'completions' or 'sglang', prompt_format 'ids' or 'text'")
        if scoring_api == "sglang" and prompt_format == "text":
            raise ValueError("SGLang's /generate takes token ids: prompt_format must be 'ids'")
        self.model = model
        self.base_url = _normalize_base_url(base_url)
        self.api_key = api_key if api_key is not None else os.environ.get(API_KEY_ENV) or None
        self.timeout = timeout
        self.max_retries = max_retries
        self.backoff = backoff
        self.max_backoff = max_backoff
        self.endpoint: Endpoint = endpoint
        self.concurrency = concurrency
        self.structured_output: StructuredOutput = structured_output
        self.supports_json_schema = structured_output != "off"
        self.sleep: Callable[[float], None] = time.sleep
        self.identity = ModelIdentity(backend="openai", name=model, revision=self.base_url)
        self.scoring_api: ScoringAPI = scoring_api
        self.prompt_format: PromptFormat = prompt_format
        self.tokenizer = None
        if tokenizer is not None:
            from talkdem.llm.backends.served_tokenizer import load_tokenizer

            self.tokenizer = load_tokenizer(tokenizer, add_bos)
            self.supports_loglikelihood = True
            # A scoring run's identity is the served model and the tokenizer that split its prompts, not the URL:
            # shards scored by several servers of one model are one run.
            self.identity = ModelIdentity(
                backend="openai", name=model, revision=f"tokenizer {self.tokenizer.name} {self.tokenizer.revision}"
            )
        self.server_root = self.base_url.removesuffix("/v1")
        # A server on this machine is never reached through a proxy named in *_proxy variables.
        local = urllib.parse.urlsplit(self.base_url).hostname in ("127.0.0.1", "localhost", "::1")
        self._opener = urllib.request.build_opener(urllib.request.ProxyHandler({})) if local else None

    # -- the interface --------------------------------------------------------------------------------
    def loglikelihood(self, requests: Sequence[LoglikelihoodRequest]) -> list[float]:
        if self.tokenizer is None:
            raise LoglikelihoodUnsupportedError(
                f"{self.identity.key()}: an OpenAI-compatible chat endpoint gives no prompt log-likelihoods; "
                "use the generative planner (SayCanConfig(mode='generative'), `talkdem run --planner generative`), "
                "give the served model's tokenizer to score over /v1/completions or SGLang "
                "(`--model-arg tokenizer=NAME`), or a local backend (hf, llamacpp, vllm)"
            )
        return loglikelihood_by_context(requests, self.score_continuations)

    def run_info(self) -> dict[str, str]:
        """What a run header records about the server (no API key)."""
        info = {"base_url": self.base_url, "served_model": self.model}
        if self.tokenizer is not None:
            info.update(
                tokenizer=self.tokenizer.name,
                tokenizer_revision=self.tokenizer.revision,
                scoring_api=self.scoring_api,
                prompt_format=self.prompt_format,
            )
        return info

    # -- scoring --------------------------------------------------------------------------------------
    def encode(self, text: str) -> list[int]:
        if self.tokenizer is None:
            raise LoglikelihoodUnsupportedError(f"{self.identity.key()}: no tokenizer given")
        return self.tokenizer.encode(text)

    def token_count(self, text: str) -> int:
        return len(self.encode(text)) if self.tokenizer is not None else super().token_count(text)

    def score_continuations(self, context: str, continuations: Sequence[str]) -> list[float]:
        """Summed log p(continuation | context) per continuation: one request per step (`ids`, SGLang), or one
        per continuation (`text`)."""
        if self.tokenizer is None:
            return self.loglikelihood([LoglikelihoodRequest(context, c) for c in continuations])
        tokenizer = self.tokenizer
        context_ids = tuple(tokenizer.context_ids(context))
        bos = tokenizer.bos_id is not None
        requests = []
        for continuation in continuations:
            ids = tuple(tokenizer.encode(continuation))
            if not ids or not context_ids:
                raise ValueError("the context and every continuation must have at least one token")
            requests.append(ScoringRequest(context_ids, ids, context + continuation, continuation, bos))
        if self.scoring_api == "sglang":
            return self._score_sglang(requests)
        if self.prompt_format == "text":
            return [self._score_text(request) for request in requests]
        response = self._post("/completions", completions_body(self.model, requests, "ids"))
        choices = self._choices_by_index(response, len(requests))
        return [
            read_completions_choice(choice, request, tokenizer.piece, f"{self.base_url}/completions")
            for choice, request in zip(choices, requests, strict=True)
        ]

    def _score_text(self, request: ScoringRequest) -> float:
        assert self.tokenizer is not None
        served = self._post_url(self.server_root + "/extras/tokenize", {"input": request.text, "model": self.model})
        tokens = served.get("tokens")
        if tokens != request.ids:
            raise ScoringProtocolError(
                f"{self.server_root}/extras/tokenize splits {request.continuation!r} after its context otherwise "
                f"than the tokenizer {self.tokenizer.name} ({len(tokens) if isinstance(tokens, list) else '?'} "
                f"tokens there, {len(request.ids)} here): the server runs another tokenizer or BOS rule"
            )
        response = self._post("/completions", completions_body(self.model, [request], "text"))
        (choice,) = self._choices_by_index(response, 1)
        return read_completions_choice(choice, request, self.tokenizer.piece, f"{self.base_url}/completions")

    def _score_sglang(self, requests: Sequence[ScoringRequest]) -> list[float]:
        url = self.server_root + "/generate"
        answer = self._post_url(url, sglang_body(requests), expect=list)
        if not isinstance(answer, list) or len(answer) != len(requests):
            raise ScoringProtocolError(f"{url}: expected a list of {len(requests)} answers")
        return [read_sglang_item(item, request, url) for item, request in zip(answer, requests, strict=True)]

    def _choices_by_index(self, response: dict[str, Any], count: int) -> list[dict[str, Any]]:
        choices = response.get("choices")
        if not isinstance(choices, list) or len(choices) != count or not all(isinstance(c, dict) for c in choices):
            raise ScoringProtocolError(f"{self.base_url}/completions: expected {count} choices")
        by_index = sorted(choices, key=lambda c: c.get("index", -1))
        if [c.get("index") for c in by_index] != list(range(count)):
            raise ScoringProtocolError(f"{self.base_url}/completions: choice indices are not 0..{count - 1}")
        return by_index

    def generate(self, requests: Sequence[GenerateRequest]) -> list[str]:
        if self.concurrency == 1 or len(requests) <= 1:
            return [self._generate_one(request) for request in requests]
        with ThreadPoolExecutor(max_workers=self.concurrency) as pool:
            return list(pool.map(self._generate_one, requests))

    # -- one request ----------------------------------------------------------------------------------
    def _generate_one(self, request: GenerateRequest) -> str:
        # A plain completion (`chat=False`) goes to /v1/completions unless the endpoint is chat only.
        if self.endpoint == "chat" or (self.endpoint == "auto" and request.chat):
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

    def _response_format(self, request: GenerateRequest) -> dict[str, Any]:
        schema = request.schema()
        if schema is None or self.structured_output == "off":
            return {}
        if self.structured_output == "json_object":
            return {"response_format": {"type": "json_object", "schema": schema}}
        return {
            "response_format": {
                "type": "json_schema",
                "json_schema": {"name": "output", "schema": schema, "strict": True},
            }
        }

    def _chat(self, request: GenerateRequest) -> str:
        body = {**self._common_fields(request), **self._response_format(request), "messages": request.messages()}
        choice = self._first_choice(self._post("/chat/completions", body))
        message = choice.get("message") or {}
        return str(message.get("content") or "")

    def _completion(self, request: GenerateRequest) -> str:
        # /v1/completions has no standard response_format; vLLM's and llama.cpp's servers accept it there too.
        body = {**self._common_fields(request), **self._response_format(request), "prompt": request.completion_text()}
        return str(self._first_choice(self._post("/completions", body)).get("text") or "")

    def _first_choice(self, response: dict[str, Any]) -> dict[str, Any]:
        choices = response.get("choices")
        if not isinstance(choices, list) or not choices or not isinstance(choices[0], dict):
            raise EndpointError(f"{self.base_url}: a response without choices: {json.dumps(response)[:300]}")
        first: dict[str, Any] = choices[0]
        return first

    def _post(self, route: str, body: dict[str, Any]) -> dict[str, Any]:
        """POST JSON to a route under the base URL with retries; the parsed JSON object."""
        answer = self._post_url(self.base_url + route, body)
        assert isinstance(answer, dict)
        return answer

    def _post_url(self, url: str, body: dict[str, Any], expect: type = dict) -> Any:
        """POST JSON with retries; the parsed JSON answer (an object, or `expect`)."""
        payload = json.dumps(body).encode()
        headers = {"Content-Type": "application/json", "Accept": "application/json"}
        if self.api_key:
            headers["Authorization"] = f"Bearer {self.api_key}"
        last_failure, retry_after = "", 0.0
        for attempt in range(self.max_retries + 1):
            if attempt:
                self.sleep(min(max(self.backoff * 2 ** (attempt - 1), retry_after), self.max_backoff))
            try:
                return self._post_once(url, payload, headers, expect)
            except _Retryable as failure:
                last_failure, retry_after = str(failure), failure.retry_after or 0.0
        raise EndpointError(
            f"{url}: no answer after {self.max_retries + 1} attempts (backoff from {self.backoff} s); "
            f"last failure: {last_failure}"
        )

    def _post_once(self, url: str, payload: bytes, headers: dict[str, str], expect: type = dict) -> Any:
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
        except UnicodeDecodeError as error:  # json.loads decodes bytes as UTF-8/16/32 before parsing
            raise _Retryable(
                f"an answer that is not UTF-8 text (byte {error.start}: {raw[error.start : error.start + 8]!r})"
            ) from error
        except json.JSONDecodeError as error:
            raise _Retryable(f"an answer that is not JSON: {raw[:200]!r}") from error
        if not isinstance(parsed, expect):
            raise EndpointError(f"{url}: expected a JSON {expect.__name__}, got {raw[:200]!r}")
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
