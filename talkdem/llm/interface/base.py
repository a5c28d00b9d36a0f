"""The one small interface every LLM backend implements."""

from __future__ import annotations

import hashlib
from abc import ABC, abstractmethod
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import ClassVar

from talkdem.llm.interface.options import BackendOption
from talkdem.llm.interface.requests import (
    ChoiceRequest,
    GenerateRequest,
    LoglikelihoodRequest,
    ModelRequest,
    ScoreRequest,
)

__all__ = [
    "BestContinuation",
    "LanguageModel",
    "ModelIdentity",
    "answer_requests",
    "cut_at_stop",
    "file_sha256",
    "loglikelihood_by_context",
]


@dataclass(frozen=True)
class ModelIdentity:
    """What makes two models the same for caching and for result files."""

    backend: str
    name: str
    """Path, model id or served model name as the user gave it."""
    revision: str = ""
    """A content hash of the weights file (GGUF) or the hub revision, when known."""
    scoring: str = ""
    """How the backend lays out its computation where that moves scores (llama.cpp: the context's batch
    layout), so that runs and cached scores of two layouts are never pooled ("" where it does not)."""

    def key(self) -> str:
        base = f"{self.backend}:{self.name}@{self.revision}"
        return f"{base}+{self.scoring}" if self.scoring else base

    def to_header(self) -> dict[str, str]:
        """The run header's `model` field."""
        header = {"backend": self.backend, "name": self.name, "revision": self.revision}
        return {**header, "scoring": self.scoring} if self.scoring else header


@dataclass(frozen=True)
class BestContinuation:
    """The winner of one SayCan step under sum scoring."""

    index: int
    """Position of the winning continuation in the input."""
    score: float
    """Its summed log-probability (nats)."""
    tokens_evaluated: int = 0
    """Candidate tokens run through the model (0: not counted, every candidate was scored in full)."""
    expansions: int = 0
    """Trie nodes whose next-token distribution was needed (branch and bound; 0 otherwise)."""


class LanguageModel(ABC):
    """A backend answers batches of requests; the planner never talks to a model any other way.

    A backend implements `loglikelihood` and `generate`. The planner's three scoring calls below have
    defaults built on `loglikelihood`; a backend overrides them when it can do better (one pass over a
    shared prefix, an exact branch-and-bound search, a real tokenizer), and must give the same answers.
    """

    identity: ModelIdentity
    options: ClassVar[tuple[BackendOption, ...]] = ()
    """The constructor options a user may set by name (`--model-arg KEY=VALUE`, a sweep's `model_args:`), each
    with its type; `talkdem.llm.interface.options` parses and checks them against this declaration."""
    supports_loglikelihood: bool = True
    """False for chat endpoints, which give no prompt log-likelihoods (planners then use generation)."""
    supports_json_schema: bool = False
    """True when `generate` constrains decoding to a request's `json_schema` (llama.cpp grammars, vLLM guided
    decoding, an OpenAI-compatible server's `response_format`); False: the schema is ignored, output is free text."""

    @abstractmethod
    def loglikelihood(self, requests: Sequence[LoglikelihoodRequest]) -> list[float]:
        """Summed log-probabilities (nats), one per request, in request order."""

    @abstractmethod
    def generate(self, requests: Sequence[GenerateRequest]) -> list[str]:
        """Greedy completions, one per request, cut at the request's stop strings."""

    def score_continuations(self, context: str, continuations: Sequence[str]) -> list[float]:
        """Summed log-probability of each continuation after `context` (one SayCan step, every skill)."""
        return self.loglikelihood([LoglikelihoodRequest(context, c) for c in continuations])

    def best_continuation(self, context: str, continuations: Sequence[str]) -> BestContinuation:
        """The continuation with the highest summed log-probability; ties go to the earlier one."""
        scores = self.score_continuations(context, continuations)
        best = max(range(len(scores)), key=lambda i: (scores[i], -i))
        return BestContinuation(best, scores[best])

    def best_continuations(self, requests: Sequence[ChoiceRequest]) -> list[BestContinuation]:
        """The answers to the choice requests of every episode in flight (one per request, in order).

        This default answers them one at a time; a backend that can run many episodes' work in one batch
        (the multi-sequence llama.cpp scorer) overrides it and must give the same choices up to its numbers'
        documented noise."""
        return [self.best_continuation(r.context, r.continuations) for r in requests]

    streams_choices: bool = False
    """True when the backend answers choice requests continuously (`submit_choice`, `advance_choices`): the
    scheduler then hands it each episode's choice as soon as the episode asks, and takes answers back as they
    come, so that one episode's next step can share a batch with another's unfinished search."""

    def submit_choice(self, request: ChoiceRequest) -> None:
        """Open a choice (continuous backends only, `streams_choices`)."""
        raise NotImplementedError(f"{type(self).__name__} does not stream choices")

    def advance_choices(self) -> list[tuple[int, BestContinuation]]:
        """Do one batch of work on the open choices; the (session, answer) of those it finished."""
        raise NotImplementedError(f"{type(self).__name__} does not stream choices")

    def score_requests(self, requests: Sequence[ScoreRequest]) -> list[list[float]]:
        """Every continuation's score for each request of every episode in flight (default: one at a time)."""
        return [self.score_continuations(r.context, r.continuations) for r in requests]

    def end_session(self, session: int) -> None:  # noqa: B027 (a hook: most backends keep no such state)
        """The episode in flight as `session` has ended: a backend that keeps per-episode state may free it."""

    def run_info(self) -> dict[str, str]:
        """What a run header records about where the model runs beyond its identity (a server's URL, the
        served model name, the tokenizer); empty for in-process backends."""
        return {}

    def runtime(self) -> dict[str, str]:
        """The libraries that compute this model's numbers in this process, with versions and build features
        (llama.cpp: the llama-cpp-python version and the CPU features it was compiled for), recorded per sitting
        in a run's header (`runtimes`) because scores move with them; empty where the computation happens
        elsewhere (a server) or is not described."""
        return {}

    def token_count(self, text: str) -> int:
        """Tokens in `text`, the divisor of mean scoring. Backends with a tokenizer count tokens; this
        default counts whitespace-separated words (an approximation for tokenizer-less endpoints)."""
        return len(text.split())


def loglikelihood_by_context(
    requests: Sequence[LoglikelihoodRequest], score_continuations: Callable[[str, list[str]], list[float]]
) -> list[float]:
    """Answer requests in order, scoring all continuations of one context in one call (SayCan's batch shape)."""
    by_context: dict[str, list[int]] = {}
    for i, request in enumerate(requests):
        by_context.setdefault(request.context, []).append(i)
    results = [0.0] * len(requests)
    for context, indices in by_context.items():
        scores = score_continuations(context, [requests[i].continuation for i in indices])
        for i, score in zip(indices, scores, strict=True):
            results[i] = score
    return results


def cut_at_stop(text: str, stop: Sequence[str]) -> str:
    """Text up to the first stop string (stop strings never appear in a completion)."""
    cut = len(text)
    for marker in stop:
        if marker and (at := text.find(marker)) != -1:
            cut = min(cut, at)
    return text[:cut]


def file_sha256(path: Path, chunk: int = 1 << 20) -> str:
    """Content hash of a weights file: the model identity must change when the weights change."""
    digest = hashlib.sha256()
    with path.open("rb") as handle:
        while block := handle.read(chunk):
            digest.update(block)
    return digest.hexdigest()


def answer_requests(model: LanguageModel, requests: Sequence[ModelRequest]) -> list[object]:
    """Answers to a mixed list of requests, in order, asking `model` once per kind (lm-evaluation-harness's
    shape: the backend sees every pending request of a kind together)."""
    answers: list[object] = [None] * len(requests)
    choices = [(i, r) for i, r in enumerate(requests) if isinstance(r, ChoiceRequest)]
    generations = [(i, r) for i, r in enumerate(requests) if isinstance(r, GenerateRequest)]
    if choices:
        for (i, _), found in zip(choices, model.best_continuations([r for _, r in choices]), strict=True):
            answers[i] = found
    if generations:
        for (i, _), text in zip(generations, model.generate([r for _, r in generations]), strict=True):
            answers[i] = text
    scores = [(i, r) for i, r in enumerate(requests) if isinstance(r, ScoreRequest)]
    if scores:
        for (i, _), values in zip(scores, model.score_requests([r for _, r in scores]), strict=True):
            answers[i] = values
    return answers
