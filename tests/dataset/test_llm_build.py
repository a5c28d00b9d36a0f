"""The LLM generator on the embedded default model (SmolLM2-135M through transformers): real generations,
greedy and reproducible on the first attempt, seeded sampling on regenerations, rows verified like the rules
generator's.
"""

from __future__ import annotations

import pytest

from builders.build import build_unit
from builders.generation.llm import LLMGenerator
from talkdem.llm.backends.hf import HFCausalLM
from talkdem.speech import GenerationRequest
from talkdem.tasks import get_task

POTATO = "trial_T20190909_152050_792044"


@pytest.fixture(scope="module")
def generator() -> LLMGenerator:
    return LLMGenerator(HFCausalLM("smollm2-135m-instruct", threads=2), max_new_tokens=40)


@pytest.mark.slow
def test_greedy_first_attempt_is_reproducible_and_regeneration_differs(generator: LLMGenerator) -> None:
    task = get_task(POTATO)
    first = GenerationRequest(task, "clean", 0, "", seed=5)
    retry = GenerationRequest(task, "clean", 0, "", seed=5, attempt=2)
    other_seed = GenerationRequest(task, "clean", 0, "", seed=6, attempt=2)
    greedy, sampled, sampled_other = generator.generate([first, retry, other_seed])
    assert greedy and sampled and sampled_other
    assert generator.generate([first, retry]) == [greedy, sampled], "same request, same text"
    assert len({greedy, sampled, sampled_other}) == 3, "a regeneration must not repeat the greedy text"


@pytest.mark.slow
def test_rows_record_the_model_and_their_verification(monkeypatch: pytest.MonkeyPatch, generator: LLMGenerator) -> None:
    # One pattern keeps the test short: the unit still runs the clean control, verification and regeneration.
    rows = build_unit(generator, get_task(POTATO), base_seed=0, patterns=("topic_drift",))
    assert [(r["pattern"], r["level"]) for r in rows] == [
        ("clean", 0),
        ("topic_drift", 1),
        ("topic_drift", 2),
        ("topic_drift", 3),
    ]
    for row in rows:
        assert row["generator"] == "llm:smollm2-135m-instruct"
        assert row["prompt_version"].startswith("v1+")
        assert row["instruction"].strip()
        assert 1 <= row["verification"]["attempts"] <= 3
        assert row["verification"]["passed"] or row["verification"]["attempts"] == 3
