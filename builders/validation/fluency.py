"""Fluency: each cell's perplexity relative to the clean controls, under a model the generator never ranks with.

Every instruction is scored by SmolLM2-135M-Instruct (llama.cpp, one thread) as a continuation of a fixed
neutral context; its mean negative log-likelihood per token, exponentiated, is its perplexity. A cell's
figure is the mean perplexity of its instructions over the mean perplexity of the clean controls, so 1.0
reads "as fluent as the clean requests" and 1.5 "half again as surprising". Scores are cached in a file
keyed by the model's identity and each text's hash: a rerun on a rebuilt dataset scores only new texts.
"""

from __future__ import annotations

import hashlib
import json
import math
import sys
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from talkdem.files import replace_file

__all__ = [
    "CONTEXT",
    "FLUENCY_MODEL",
    "FluencyScorer",
    "cell_fluency",
    "default_cache_file",
    "perplexity",
]

FLUENCY_MODEL = "smollm2-135m-instruct"
"""Not the model that ranks the generator's candidates (issue 19 ranks with the default planner model)."""

CONTEXT = "Here is what a person said to a household robot:\n"
"""The fixed context every instruction continues: one short, neutral frame, the same for every cell, so that
the first token is not scored from nothing (SmolLM2 has no beginning-of-text token)."""

_BATCH = 64


def perplexity(nll_per_token: float) -> float:
    return math.exp(nll_per_token)


def default_cache_file(revision: str) -> Path:
    from talkdem.paths import cache_dir

    return cache_dir() / "validation" / f"fluency-{revision[:16]}.json"


@dataclass
class FluencyScorer:
    """Mean NLL per token of texts under one model, with a persistent cache (text hash -> [nll, tokens])."""

    model: Any
    """A `talkdem.llm.interface.base.LanguageModel` with log-likelihoods and a tokenizer."""
    cache_file: Path
    context: str = CONTEXT

    def __post_init__(self) -> None:
        self._cache: dict[str, list[float]] = {}
        if self.cache_file.is_file():
            stored = json.loads(self.cache_file.read_text())
            if stored.get("model") == self.model.identity.key() and stored.get("context") == self.context:
                self._cache = stored["scores"]

    @classmethod
    def default(cls, cache_file: Path | None = None, threads: int = 1) -> FluencyScorer:
        from talkdem.llm.interface.registry import load_model

        model = load_model("llamacpp", FLUENCY_MODEL, threads=threads, n_ctx=512)
        return cls(model, cache_file or default_cache_file(model.identity.revision))

    @property
    def identity(self) -> dict[str, str]:
        identity = self.model.identity
        return {"backend": identity.backend, "name": identity.name, "sha256": identity.revision}

    def _key(self, text: str) -> str:
        return hashlib.sha256(text.encode()).hexdigest()

    def _save(self) -> None:
        self.cache_file.parent.mkdir(parents=True, exist_ok=True)
        payload = {"model": self.model.identity.key(), "context": self.context, "scores": self._cache}
        replace_file(self.cache_file, json.dumps(payload, sort_keys=True))

    def nll_per_token(self, texts: Sequence[str], progress: Callable[[int, int], None] | None = None) -> list[float]:
        """Mean negative log-likelihood per token of each text (nats), scoring only texts not cached."""
        from talkdem.llm.interface.requests import LoglikelihoodRequest

        # in hash order, not text order: an interrupted run leaves a cache that is a random sample of every cell
        todo = sorted({t for t in texts if self._key(t) not in self._cache}, key=self._key)
        for start in range(0, len(todo), _BATCH):
            batch = todo[start : start + _BATCH]
            sums = self.model.loglikelihood([LoglikelihoodRequest(self.context, t) for t in batch])
            for text, total in zip(batch, sums, strict=True):
                tokens = max(self.model.token_count(text), 1)
                self._cache[self._key(text)] = [-total / tokens, float(tokens)]
            self._save()  # a killed run keeps what it scored
            if progress is not None:
                progress(min(start + _BATCH, len(todo)), len(todo))
        return [self._cache[self._key(t)][0] for t in texts]


def cell_fluency(nll: Sequence[float], clean_nll: Sequence[float]) -> dict[str, float]:
    """Mean perplexity of a cell, of the clean controls, and their ratio."""
    cell = sum(perplexity(x) for x in nll) / len(nll)
    clean = sum(perplexity(x) for x in clean_nll) / len(clean_nll)
    return {
        "perplexity": cell,
        "clean_perplexity": clean,
        "relative_perplexity": cell / clean,
        "mean_nll_per_token": sum(nll) / len(nll),
    }


def print_progress(done: int, total: int) -> None:
    """A one-line progress report on stderr (what the command passes as `progress`)."""
    print(f"fluency: {done}/{total} new instructions scored", file=sys.stderr, flush=True)
