"""The result cache: hits never reach the model, and a different model identity never hits."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import pytest

from talkdem.llm.interface.base import LanguageModel, ModelIdentity
from talkdem.llm.interface.requests import GenerateRequest, LoglikelihoodRequest
from talkdem.llm.scoring.cache import CachedLM, cache_key


class CountingLM(LanguageModel):
    """A stand-in model for unit tests only: deterministic answers, every call recorded."""

    def __init__(self, revision: str = "r1", offset: float = 0.0) -> None:
        self.identity = ModelIdentity(backend="test", name="counting", revision=revision)
        self.offset = offset
        self.calls: list[tuple[str, int]] = []

    def loglikelihood(self, requests: Sequence[LoglikelihoodRequest]) -> list[float]:
        self.calls.append(("loglikelihood", len(requests)))
        return [-len(r.context) / 7 - len(r.continuation) / 3 + self.offset for r in requests]

    def generate(self, requests: Sequence[GenerateRequest]) -> list[str]:
        self.calls.append(("generate", len(requests)))
        return [f"{r.prompt[::-1]}|{r.max_new_tokens}|{self.identity.revision}" for r in requests]


class ScoringLM(CountingLM):
    def score_continuations(self, context: str, continuations: Sequence[str]) -> list[float]:
        self.calls.append(("score_continuations", len(continuations)))
        return [-len(context) / 7 - len(c) / 3 + 0.1 for c in continuations]

    def token_count(self, text: str) -> int:
        return len(text)


def test_hits_are_answered_without_the_model(tmp_path: Path) -> None:
    inner = CountingLM()
    cached = CachedLM(inner, tmp_path / "cache.sqlite")
    requests = [LoglikelihoodRequest("ctx", " a"), LoglikelihoodRequest("ctx", " bb")]
    first = cached.loglikelihood(requests)
    assert first == inner.loglikelihood(requests)
    inner.calls.clear()
    assert cached.loglikelihood(requests) == first
    assert inner.calls == [] and cached.hits == 2 and cached.misses == 2


def test_only_misses_go_to_the_model_in_order(tmp_path: Path) -> None:
    inner = CountingLM()
    cached = CachedLM(inner, tmp_path / "cache.sqlite")
    cached.loglikelihood([LoglikelihoodRequest("ctx", " b")])
    inner.calls.clear()
    mixed = [LoglikelihoodRequest("ctx", c) for c in (" a", " b", " ccc", " a")]
    assert cached.loglikelihood(mixed) == inner.loglikelihood(mixed)
    assert inner.calls[0] == ("loglikelihood", 2), "one call for the two distinct misses"


def test_generation_is_cached_with_its_arguments(tmp_path: Path) -> None:
    inner = CountingLM()
    cached = CachedLM(inner, tmp_path / "cache.sqlite")
    short, long = GenerateRequest("hello", max_new_tokens=4), GenerateRequest("hello", max_new_tokens=40)
    assert cached.generate([short]) == ["olleh|4|r1"]
    assert cached.generate([long]) == ["olleh|40|r1"], "max_new_tokens is part of the key"
    assert cached.generate([GenerateRequest("hello", max_new_tokens=4, stop=(".",))]) == ["olleh|4|r1"]
    assert len(inner.calls) == 3
    assert cached.generate([short, long]) == ["olleh|4|r1", "olleh|40|r1"] and len(inner.calls) == 3


def test_a_different_identity_never_hits(tmp_path: Path) -> None:
    path = tmp_path / "shared.sqlite"
    requests = [LoglikelihoodRequest("ctx", " a")]
    CachedLM(CountingLM(revision="r1"), path).loglikelihood(requests)
    CachedLM(CountingLM(revision="r1"), path).generate([GenerateRequest("p")])
    other = CountingLM(revision="r2", offset=1.0)
    cached_other = CachedLM(other, path)
    assert cached_other.loglikelihood(requests) == other.loglikelihood(requests)
    assert cached_other.generate([GenerateRequest("p")]) == ["p|64|r2"]
    assert cached_other.hits == 0 and cached_other.misses == 2
    for field in ("backend", "name", "revision"):
        identity = ModelIdentity(backend="test", name="counting", revision="r1")
        changed = ModelIdentity(**{**identity.__dict__, field: "x"})
        assert cache_key(identity.key(), "loglikelihood", ["ctx", " a"]) != cache_key(
            changed.key(), "loglikelihood", ["ctx", " a"]
        )


def test_results_persist_across_instances(tmp_path: Path) -> None:
    path = tmp_path / "cache.sqlite"
    with CachedLM(CountingLM(), path) as cached:
        expected = cached.loglikelihood([LoglikelihoodRequest("ctx", " a")])
    inner = CountingLM()
    with CachedLM(inner, path) as reopened:
        assert reopened.loglikelihood([LoglikelihoodRequest("ctx", " a")]) == expected
        assert len(reopened) == 1
    assert inner.calls == []


def test_the_scoring_calls_go_through_the_cache_and_the_inner_fast_path(tmp_path: Path) -> None:
    inner = ScoringLM()
    cached = CachedLM(inner, tmp_path / "b.sqlite")
    first = cached.score_continuations("ctx", [" a", " bb"])
    assert first == pytest.approx(inner.score_continuations("ctx", [" a", " bb"]))
    inner.calls.clear()
    assert cached.score_continuations("ctx", [" bb", " a", " c"])[:2] == [first[1], first[0]]
    assert inner.calls == [("score_continuations", 1)], "only the new candidate reaches the model"
    assert cached.token_count("ab") == 2 == inner.token_count("ab")


def test_best_continuation_is_cached_and_equals_full_scoring(tmp_path: Path) -> None:
    inner = ScoringLM()
    cached = CachedLM(inner, tmp_path / "c.sqlite")
    candidates = [" bbb", " a", " cc"]
    found = cached.best_continuation("ctx", candidates)
    scores = inner.score_continuations("ctx", candidates)
    assert found.index == max(range(3), key=lambda i: scores[i]) == 1
    inner.calls.clear()
    assert cached.best_continuation("ctx", candidates) == found and inner.calls == []
    assert cached.best_continuation("ctx", candidates[:1]).index == 0, "another candidate list is another entry"


def test_the_default_interface_is_built_on_loglikelihood() -> None:
    plain = CountingLM()
    assert plain.score_continuations("ctx", [" a", " bb"]) == plain.loglikelihood(
        [LoglikelihoodRequest("ctx", " a"), LoglikelihoodRequest("ctx", " bb")]
    )
    assert plain.best_continuation("ctx", [" bb", " a", " a"]).index == 1, "ties go to the earlier candidate"
    assert plain.token_count("find a mug") == 3
