"""SayCan log-likelihood scoring through a serving engine: the request bodies and the reading of the answers.

Two wire formats, both giving the log-probabilities of prompt tokens:

- OpenAI-compatible `/v1/completions` with `echo: true, logprobs: 1, max_tokens: 1` (vLLM; llama-cpp-python's
  server). The answer lists every echoed prompt token and its log-probability (the first one's is `null`: no
  distribution precedes it), then the one generated token. A continuation's score is the sum of its tokens'
  entries, located by token count from the end of the context, never by `text_offset` (a running sum of
  decoded token lengths, which is not a position in our string). Choices are matched to prompts by `index`.
  - `ids` prompts (vLLM): token-id lists, all candidates of a step in one request; the server cannot split
    them differently from us.
  - `text` prompts (llama-cpp-python's server, which takes one string per request and tokenizes it itself):
    the server's own split is first read from `/extras/tokenize` and must equal ours.
- SGLang's native `/generate` with `input_ids`, `return_logprob`, `logprob_start_len` (the context length:
  only the continuation's entries come back) and `max_new_tokens: 0`; SGLang reuses its cached prefix.

Every answer is checked against what was sent: the number of echoed entries, and the echoed token ids or text
of the continuation. llama-cpp-python's server (0.3.x) pairs each echoed token with the distribution *after* it
when the model has no BOS token (SmolLM2, Qwen2.5): that answer carries no entry for the generated token, and is
refused with an error that says so, rather than scored wrongly.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, Literal

__all__ = [
    "LOGPROB_TOLERANCE",
    "PromptFormat",
    "ScoringProtocolError",
    "ScoringRequest",
    "checked_logprob",
    "completions_body",
    "read_completions_choice",
    "read_sglang_item",
    "sglang_body",
]

PromptFormat = Literal["ids", "text"]


class ScoringProtocolError(ValueError):
    """A server answer that does not line up with the tokens that were sent."""


@dataclass(frozen=True)
class ScoringRequest:
    """One candidate: the context's tokens (with BOS when the model takes one) and the continuation's."""

    context_ids: tuple[int, ...]
    continuation_ids: tuple[int, ...]
    text: str = ""
    """context + continuation as text (`text` prompts)."""
    continuation: str = ""
    starts_with_bos: bool = False
    """The context's first token is the model's BOS token."""

    @property
    def ids(self) -> list[int]:
        return [*self.context_ids, *self.continuation_ids]


def completions_body(model: str, prompts: Sequence[ScoringRequest], prompt_format: PromptFormat) -> dict[str, Any]:
    """A `/v1/completions` body asking for the prompt tokens' log-probabilities (greedy, one new token)."""
    prompt: Any
    if prompt_format == "ids":
        prompt = [request.ids for request in prompts]
    else:
        prompt = prompts[0].text if len(prompts) == 1 else [request.text for request in prompts]
    return {"model": model, "prompt": prompt, "echo": True, "logprobs": 1, "max_tokens": 1, "temperature": 0.0}


def _echo_text(token: object) -> str:
    return token if isinstance(token, str) else ""


LOGPROB_TOLERANCE = 1e-4
"""How far above 0 a served log-probability may be and still count as 0. A server computes log-softmax in
float32 (vLLM, SGLang): for a token of probability ~1 the result `x - logsumexp(x)` is 0 up to the rounding
of numbers the size of the logits (~1e-6 for logits of tens). Anything larger is no rounding: a probability
above 1, a server bug or a forged answer; it would also break branch and bound, which relies on partial
sums never growing (so values within the tolerance are counted as exactly 0)."""


def checked_logprob(value: Any, where: str, what: str) -> float:
    """`value` as a log-probability: a finite number, at most 0 (within `LOGPROB_TOLERANCE`), else one
    `ScoringProtocolError` line naming `where` and `what`."""
    if not isinstance(value, int | float) or isinstance(value, bool) or math.isnan(value):
        raise ScoringProtocolError(f"{where}: {what} is {value!r}: not a number")
    if not math.isfinite(value):
        raise ScoringProtocolError(f"{where}: {what} is {value!r}: a log-probability must be finite")
    if value > LOGPROB_TOLERANCE:
        raise ScoringProtocolError(
            f"{where}: {what} is {value!r}: a log-probability is at most 0 (a probability above 1)"
        )
    return min(float(value), 0.0)


def read_completions_choice(choice: dict[str, Any], request: ScoringRequest, piece: Any, where: str) -> float:
    """The continuation's summed log-probability from one echoed choice, after checking its alignment.

    `piece(token_id) -> bytes` decodes one token, to compare the echoed continuation text.
    """
    logprobs = choice.get("logprobs")
    if not isinstance(logprobs, dict):
        raise ScoringProtocolError(f"{where}: a choice without logprobs (does the server support echo?)")
    tokens, values = logprobs.get("tokens"), logprobs.get("token_logprobs")
    if not isinstance(tokens, list) or not isinstance(values, list) or len(tokens) != len(values):
        raise ScoringProtocolError(f"{where}: logprobs without matching 'tokens' and 'token_logprobs' lists")
    ids = request.ids
    n, n_context = len(ids), len(request.context_ids)
    has_bos_echo = len(values) == n + 1  # every prompt token (BOS included) and the generated one
    bos_dropped = len(values) == n and request.starts_with_bos  # llama-cpp-python does not echo BOS
    if not (has_bos_echo or bos_dropped):
        raise ScoringProtocolError(
            f"{where}: {len(values)} echoed entries for {n} prompt tokens (expected {n + 1}: the prompt and the "
            "one generated token). llama-cpp-python's server (0.3.x) answers so for models without a BOS token, "
            "pairing each token with the distribution after it; its scores would be wrong. Use a server that "
            "echoes prompt log-probabilities correctly (vLLM, SGLang) or a model with a BOS token"
        )
    offset = 0 if has_bos_echo else 1
    span = range(n_context - offset, n - offset)
    echoed = "".join(_echo_text(tokens[k]) for k in span)
    if echoed.startswith("token_id:") or "token_id:" in echoed:
        sent = [int(str(tokens[k]).removeprefix("token_id:")) for k in span]
        if sent != list(request.continuation_ids):
            raise ScoringProtocolError(f"{where}: echoed token ids {sent} are not the continuation's")
    else:
        expected = b"".join(piece(t) for t in request.continuation_ids).decode("utf-8", errors="replace")
        if "\ufffd" not in expected + echoed and _plain(echoed) != _plain(expected):
            raise ScoringProtocolError(
                f"{where}: the server echoed {echoed!r} where the continuation {expected!r} should be: its "
                "tokens are not ours (another tokenizer, or a split across the context boundary)"
            )
    return sum(checked_logprob(values[k], where, f"echoed log-probability at token {k}") for k in span)


def _plain(text: str) -> str:
    """Echoed pieces as text: SentencePiece and byte-level BPE markers mean a space."""
    return text.replace("\u2581", " ").replace("\u0120", " ").replace("\u010a", "\n")


def sglang_body(prompts: Sequence[ScoringRequest]) -> dict[str, Any]:
    """An SGLang `/generate` body: the continuation tokens' log-probabilities, nothing generated."""
    if len({len(p.context_ids) for p in prompts}) != 1:
        raise ValueError("one SGLang request scores continuations of one context")
    return {
        "input_ids": [request.ids for request in prompts],
        "sampling_params": {"max_new_tokens": 0, "temperature": 0.0},
        "return_logprob": True,
        "logprob_start_len": len(prompts[0].context_ids),
        "return_text_in_logprobs": False,
    }


def read_sglang_item(item: Any, request: ScoringRequest, where: str) -> float:
    """The continuation's summed log-probability from one `/generate` answer (`meta_info.input_token_logprobs`:
    `[logprob, token_id, text]` per prompt token from `logprob_start_len` on)."""
    meta = item.get("meta_info") if isinstance(item, dict) else None
    entries = meta.get("input_token_logprobs") if isinstance(meta, dict) else None
    if not isinstance(entries, list):
        raise ScoringProtocolError(f"{where}: an answer without meta_info.input_token_logprobs")
    want = list(request.continuation_ids)
    if len(entries) != len(want):
        raise ScoringProtocolError(
            f"{where}: {len(entries)} input log-probabilities for a continuation of {len(want)} tokens"
        )
    total = 0.0
    for k, entry in enumerate(entries):
        if not isinstance(entry, list | tuple) or len(entry) < 2:
            raise ScoringProtocolError(f"{where}: entry {k} is not [logprob, token_id, ...]")
        value, token = entry[0], entry[1]
        if token != want[k]:
            raise ScoringProtocolError(f"{where}: entry {k} is token {token}, the continuation has {want[k]}")
        total += checked_logprob(value, where, f"log-probability of entry {k}")
    return total
