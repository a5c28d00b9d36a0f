"""vLLM cannot run here (no GPU, not installed): only what runs without it is tested."""

from __future__ import annotations

import sys
from dataclasses import dataclass

import pytest

from talkdem.llm.backends.vllm_backend import VLLMLM, plan_scoring, sum_prompt_logprobs
from talkdem.llm.interface.requests import LoglikelihoodRequest


@dataclass
class Logprob:
    logprob: float


def _encode(text: str) -> list[int]:
    return [ord(ch) for ch in text]


def test_missing_vllm_gives_a_clear_error(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "vllm", None)  # an import of vllm now fails, installed or not
    with pytest.raises(ImportError, match="vLLM is not installed"):
        VLLMLM("some/model")


def test_plan_tokenizes_each_context_once_and_shares_prefix_continuations() -> None:
    seen: list[str] = []

    def encode_context(text: str) -> list[int]:
        seen.append(text)
        return _encode(text)

    requests = [
        LoglikelihoodRequest("ab", "c"),
        LoglikelihoodRequest("ab", "cd"),
        LoglikelihoodRequest("ab", "x"),
        LoglikelihoodRequest("q", "c"),
        LoglikelihoodRequest("ab", "cd"),
    ]
    plan = plan_scoring(requests, encode_context, _encode)
    assert seen == ["ab", "q"]
    expected = [_encode("abcd"), _encode("abx"), _encode("qc")]
    assert sorted(plan.sequences) == sorted(expected)
    sequence_of = [plan.sequences[index] for index, _, _ in plan.spans]
    assert sequence_of[0] == sequence_of[1] == sequence_of[4] == _encode("abcd")
    assert [(start, end) for _, start, end in plan.spans] == [(2, 3), (2, 4), (2, 3), (1, 2), (2, 4)]


def test_prompt_logprobs_are_summed_over_the_continuation_span() -> None:
    tokens = [5, 6, 7, 8]
    prompt_logprobs = [None, {6: Logprob(-1.0), 9: Logprob(-0.5)}, {7: Logprob(-2.0)}, {8: Logprob(-0.25)}]
    assert sum_prompt_logprobs(prompt_logprobs, tokens, 2, 4) == pytest.approx(-2.25)
    assert sum_prompt_logprobs(prompt_logprobs, tokens, 1, 2) == pytest.approx(-1.0)
    with pytest.raises(ValueError, match="position 0"):
        sum_prompt_logprobs(prompt_logprobs, tokens, 0, 1)


def test_empty_continuations_are_refused() -> None:
    with pytest.raises(ValueError, match="empty continuation"):
        plan_scoring([LoglikelihoodRequest("ab", "")], _encode, _encode)


def test_a_json_schema_becomes_the_structured_outputs_of_either_vllm_generation() -> None:
    from types import SimpleNamespace

    from talkdem.llm.backends.vllm_backend import guided_json_options

    @dataclass
    class Params:
        json: dict[str, object]

    schema = {"type": "object"}
    newer = SimpleNamespace(sampling_params=SimpleNamespace(StructuredOutputsParams=Params))
    older = SimpleNamespace(sampling_params=SimpleNamespace(GuidedDecodingParams=Params))
    assert guided_json_options(newer, schema) == {"structured_outputs": Params(schema)}
    assert guided_json_options(older, schema) == {"guided_decoding": Params(schema)}
    with pytest.raises(ImportError, match="no structured outputs"):
        guided_json_options(SimpleNamespace(sampling_params=SimpleNamespace(), __version__="0.1"), schema)
