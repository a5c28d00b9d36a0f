"""Strategies: what each shows the planner (CARE has its own tests under tests/care)."""

from __future__ import annotations

import pytest
from scripted_lm import ScriptedLM

from talkdem.instructions import load_memory_bank
from talkdem.planner.strategies import fixed_icl_demonstrations, load_strategy
from talkdem.schema import PATTERN_CONFIGS


def test_registry_and_did_you_mean() -> None:
    assert load_strategy("ap").name == "ap"
    with pytest.raises(ValueError, match="did you mean 'tocc'"):
        load_strategy("toc")


def test_ap_adds_the_awareness_sentence_and_vanilla_does_not() -> None:
    lm = ScriptedLM(["done"])
    assert "communication" not in load_strategy("vanilla").prepare(["hi"], lm)[0].preamble
    assert "self-corrections" in load_strategy("ap").prepare(["hi"], lm)[0].preamble


def test_tocc_shows_only_the_rewrite_and_cot_adds_an_interpretation() -> None:
    lm = ScriptedLM(["done"], generated="Put the apple in the fridge.")
    tocc = load_strategy("tocc").prepare(["um, the, the round thing, in the cold box"], lm)[0]
    assert tocc.instruction == "Put the apple in the fridge." and tocc.notes["rewrite"] == tocc.instruction
    cot = load_strategy("cot").prepare(["um, the round thing"], lm)[0]
    assert cot.instruction == "um, the round thing" and cot.interpretation == "Put the apple in the fridge."


def test_icl_uses_five_fixed_examples_one_per_pattern() -> None:
    memory = load_memory_bank()
    demos = fixed_icl_demonstrations(memory)
    assert len(demos) == 5
    by_text = {m.instruction: m for m in memory}
    assert [by_text[d.instruction].condition.pattern for d in demos] == list(PATTERN_CONFIGS)
    assert len({by_text[d.instruction].task_type for d in demos}) == 5
    assert all(d.interpretation and d.plan[-1] == "done" for d in demos)
