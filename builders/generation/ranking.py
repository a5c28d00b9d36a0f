"""Overgenerate and rank: score verified candidates by a language model's mean log-probability per token.

The rules generator draws several candidates per instruction; the build keeps those that pass verification and
keeps the one a small language model finds most probable per token (the classic overgenerate-and-rank filter:
"Is those keys" and "hide behind the butter knife" score low without a large model). Scores come from the
project's scoring backends (`talkdem.llm`, `loglikelihood` and `token_count`), so any backend can rank.

The fluency measure of the validation is computed under another model (SmolLM2-135M): ranking with that model
would make the fluency figures measure the ranking, so it is refused here.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Protocol

from talkdem.llm.interface.requests import LoglikelihoodRequest

__all__ = [
    "CONTEXT",
    "RESERVED_MODELS",
    "CandidateRanker",
    "Ranker",
    "RecordedRanker",
    "ScoringModel",
    "best_index",
    "load_ranker",
]

CONTEXT = 'At home, an older person said to their robot: "'
"""What each candidate continues; the closing quote is scored with it, so an utterance must also end well."""

RESERVED_MODELS = ("smollm2", "smollm2-135m", "smollm2-135m-instruct")
"""Models kept for the independent fluency measure: never used for ranking."""


class _Identity(Protocol):
    def key(self) -> str: ...


class ScoringModel(Protocol):
    """What ranking needs of a backend (every `talkdem.llm.LanguageModel` has it)."""

    @property
    def identity(self) -> _Identity: ...

    def loglikelihood(self, requests: Sequence[LoglikelihoodRequest]) -> list[float]: ...

    def token_count(self, text: str) -> int: ...


class CandidateRanker(Protocol):
    """What the build needs of a ranker: an id stored with every ranked row and a score per candidate text."""

    @property
    def model_id(self) -> str: ...

    def scores(self, texts: Sequence[str]) -> list[float]: ...


def best_index(scores: Sequence[float]) -> int:
    """The highest score's position; ties go to the earlier candidate (deterministic)."""
    if not scores:
        raise ValueError("no candidate to rank")
    return max(range(len(scores)), key=lambda i: (scores[i], -i))


@dataclass
class Ranker:
    """Mean log-probability per token of each utterance under one model."""

    model: ScoringModel

    @property
    def model_id(self) -> str:
        """backend:name@sha256 of the weights, stored with every ranked row."""
        return self.model.identity.key()

    def scores(self, texts: Sequence[str]) -> list[float]:
        """Mean log-probability (nats per token) of each text, in one batched call."""
        continuations = [f'{text}"' for text in texts]
        sums = self.model.loglikelihood([LoglikelihoodRequest(CONTEXT, c) for c in continuations])
        return [s / max(self.model.token_count(c), 1) for s, c in zip(sums, continuations, strict=True)]


def load_ranker(name: str | None, backend: str = "llamacpp", threads: int = 1) -> Ranker | None:
    """The ranker for `--rank-model NAME` (None or `none`: no ranking), on one thread by default."""
    if name is None or name.lower() == "none":
        return None
    if name.lower() in RESERVED_MODELS or "smollm2-135m" in name.lower():
        raise ValueError(
            f"--rank-model {name}: SmolLM2-135M is reserved for the independent fluency measure; rank with "
            "another model (e.g. qwen2.5-coder-0.5b) or none"
        )
    from talkdem.llm.interface.registry import load_model

    options = {"threads": threads} if backend == "llamacpp" else {}
    return Ranker(load_model(backend, name, **options))


@dataclass(frozen=True)
class RecordedRanker:
    """The choices a ranked build recorded in its rows, replayed without the model (`builders.replay`).

    Each kept text scores what its row recorded; every other candidate scores -inf, so the replay keeps the
    recorded text wherever it is still a verified candidate of its request, and a different row (which the
    replay's comparison then reports) wherever it is not."""

    model_id: str
    recorded: Mapping[str, float]

    @classmethod
    def from_rows(cls, rows: Iterable[Mapping[str, Any]]) -> RecordedRanker | None:
        """The ranker of one unit's rows (None when no row of it was ranked)."""
        models: set[str] = set()
        recorded: dict[str, float] = {}
        for row in rows:
            ranking = row.get("ranking") or {}
            if ranking.get("model") is None:
                continue
            models.add(ranking["model"])
            recorded[row["instruction"]] = ranking["score"]
        if not models:
            return None
        if len(models) > 1:
            raise ValueError(f"rows ranked by more than one model: {', '.join(sorted(models))}")
        return cls(models.pop(), recorded)

    def scores(self, texts: Sequence[str]) -> list[float]:
        return [self.recorded.get(text, -math.inf) for text in texts]
