"""Fluency under SmolLM2-135M: a garbled instruction is less fluent than a fluent one; scores are cached."""

from __future__ import annotations

from pathlib import Path

import pytest

from builders.validation.fluency import FluencyScorer, cell_fluency

FLUENT = "Could you put the apple in the fridge, please?"
ALSO_FLUENT = "Please take the mug to the sink and rinse it."
GARBLED = "Fridge the please apple, in put you could the?"


@pytest.mark.slow
def test_fluency_ratio_orders_garbled_after_fluent(tmp_path: Path) -> None:
    cache = tmp_path / "fluency.json"
    scorer = FluencyScorer.default(cache)
    fluent, also, garbled = scorer.nll_per_token([FLUENT, ALSO_FLUENT, GARBLED])
    assert garbled > max(fluent, also)
    ratio = cell_fluency([garbled], [fluent, also])["relative_perplexity"]
    assert ratio > 1.0
    assert cell_fluency([fluent, also], [fluent, also])["relative_perplexity"] == 1.0
    assert scorer.identity["sha256"] and scorer.identity["backend"] == "llamacpp"

    # a second scorer on the same cache file scores nothing again
    evaluated = scorer.model.tokens_evaluated
    again = FluencyScorer(scorer.model, cache)
    assert again.nll_per_token([GARBLED, FLUENT]) == [garbled, fluent]
    assert scorer.model.tokens_evaluated == evaluated
