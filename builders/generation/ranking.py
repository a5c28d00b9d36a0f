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
    "SCORE_DIGITS",
    "CandidateRanker",
    "Ranker",
    "RecordedRanker",
    "ScoringModel",
    "checked_margin",
    "choose",
    "load_ranker",
    "model_name",
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
    """What the build needs of a ranker: an id stored with every ranked row, a score per candidate, and how
    far below the best a candidate may score and still be kept (`choose`)."""

    @property
    def model_id(self) -> str: ...

    @property
    def margin(self) -> float: ...

    def score_candidates(self, candidates: Sequence[tuple[int, str]]) -> list[float]: ...


SCORE_DIGITS = 6
"""Scores are rounded before the choice, so that a replay from the scores the rows record chooses alike."""


def choose(scores: Sequence[float], margin: float = 0.0) -> int:
    """The first candidate, in draw order, that scores within `margin` (nats per token) of the best.

    A margin of 0 keeps the best (ties to the earlier candidate). A positive margin filters instead of
    maximising: the model only rejects the disfluent tail, and among the candidates it finds about as likely
    the generator's own draw stands, so the most predictable wording does not win every time (measured in
    issue 19: keeping the best raised the share of the ten most frequent Topic Drift L1 sentences from 34%
    to 44% on 83 tasks)."""
    if not scores:
        raise ValueError("no candidate to rank")
    if margin < 0:
        raise ValueError(f"the ranking margin must be >= 0, got {margin}")
    best = max(scores)
    return next(i for i, score in enumerate(scores) if score >= best - margin)


def checked_margin(margin: float) -> float:
    """`margin` as a float, or a ValueError naming `--rank-margin` (build, ranker and replay check alike)."""
    if not margin >= 0:  # also refuses NaN
        raise ValueError(f"--rank-margin must be a number >= 0 (nats per token), got {margin}")
    return float(margin)


@dataclass
class Ranker:
    """Mean log-probability per token of each utterance under one model."""

    model: ScoringModel
    margin: float = 0.0
    """Keep the first candidate within this many nats per token of the best (`choose`)."""

    def __post_init__(self) -> None:
        self.margin = checked_margin(self.margin)

    @property
    def model_id(self) -> str:
        """backend:name@sha256 of the weights, stored with every ranked row."""
        return self.model.identity.key()

    def scores(self, texts: Sequence[str]) -> list[float]:
        """Mean log-probability (nats per token) of each text, in one batched call."""
        continuations = [f'{text}"' for text in texts]
        sums = self.model.loglikelihood([LoglikelihoodRequest(CONTEXT, c) for c in continuations])
        return [s / max(self.model.token_count(c), 1) for s, c in zip(sums, continuations, strict=True)]

    def score_candidates(self, candidates: Sequence[tuple[int, str]]) -> list[float]:
        """`scores` of the candidates' texts, rounded to SCORE_DIGITS (the seeds are not needed)."""
        return [round(score, SCORE_DIGITS) for score in self.scores([text for _, text in candidates])]


def model_name(model_id: str) -> str:
    """The catalogue name (`--rank-model NAME`) inside a ranking model's id (`backend:name@sha256[+layout]`)."""
    return model_id.split(":", 1)[-1].split("@", 1)[0]


def load_ranker(name: str | None, backend: str = "llamacpp", threads: int = 1, margin: float = 0.0) -> Ranker | None:
    """The ranker for `--rank-model NAME` (None or `none`: no ranking), on one thread by default, keeping the
    first candidate within `margin` of the best."""
    if name is None or name.lower() == "none":
        return None
    if name.lower() in RESERVED_MODELS or "smollm2-135m" in name.lower():
        raise ValueError(
            f"--rank-model {name}: SmolLM2-135M is reserved for the independent fluency measure; rank with "
            "another model (e.g. qwen2.5-coder-0.5b) or none"
        )
    from talkdem.llm.interface.registry import load_model

    margin = checked_margin(margin)
    options = {"threads": threads} if backend == "llamacpp" else {}
    return Ranker(load_model(backend, name, **options), margin)


@dataclass(frozen=True)
class RecordedRanker:
    """The scores a ranked build recorded in its rows, replayed without the model (`builders.replay`).

    Each row records the score of every candidate that passed verification, by seed; a candidate the rows do
    not record scores -inf. So a replay chooses what the build chose wherever the same candidates still pass,
    and writes a different row (which the replay's comparison then reports) wherever they do not. With another
    `margin` it applies another choice rule to the same scores, without the model."""

    model_id: str
    recorded: Mapping[int, float]
    margin: float = 0.0

    @classmethod
    def from_rows(cls, rows: Iterable[Mapping[str, Any]], margin: float = 0.0) -> RecordedRanker | None:
        """The ranker of one unit's rows (None when no row of it was ranked)."""
        models: set[str] = set()
        recorded: dict[int, float] = {}
        for row in rows:
            ranking = row.get("ranking") or {}
            if ranking.get("model") is None:
                continue
            models.add(ranking["model"])
            for entry in ranking.get("scored") or [{"seed": row["seed"], "score": ranking["score"]}]:
                recorded[int(entry["seed"])] = float(entry["score"])
        if not models:
            return None
        if len(models) > 1:
            raise ValueError(f"rows ranked by more than one model: {', '.join(sorted(models))}")
        return cls(models.pop(), recorded, checked_margin(margin))

    def score_candidates(self, candidates: Sequence[tuple[int, str]]) -> list[float]:
        return [self.recorded.get(seed, -math.inf) for seed, _ in candidates]
