"""CoT's answer and TOCC's rewrite with the real default model, on the benchmark's longest instructions:
none is cut by the token budget, loops, or comes back empty (the budget's measurement: docs/strategies.md)."""

from __future__ import annotations

import pytest

from talkdem.instructions import load_instructions
from talkdem.planner.decoding import MAX_NEW_TOKENS
from talkdem.planner.strategies import load_strategy


@pytest.mark.slow
def test_no_answer_or_rewrite_is_cut_by_the_budget_on_the_longest_instructions() -> None:
    from talkdem.llm.interface.registry import load_model

    model = load_model("llamacpp", "default", threads=1)
    # The three longest instructions of the benchmark (all topic drift, level 3), by the model's own tokens.
    longest = sorted(load_instructions(), key=lambda i: (-model.token_count(i.text), i.id))[:3]
    assert model.token_count(longest[0].text) < MAX_NEW_TOKENS
    for name, key in (("tocc", "rewrite"), ("cot", "interpretation")):
        inputs = load_strategy(name).prepare([i.text for i in longest], model)
        for instruction, planner_input in zip(longest, inputs, strict=True):
            status, text = planner_input.notes[f"{key}_status"], planner_input.notes[key]
            assert status == "ok", f"{name} on {instruction.id}: {status}: {text!r}"
            assert model.token_count(text) < MAX_NEW_TOKENS // 2, f"{name} on {instruction.id}: {text!r}"
