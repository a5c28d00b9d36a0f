"""Strategies: what each shows the planner (CARE has its own tests under tests/care)."""

from __future__ import annotations

import pytest
from scripted_lm import ScriptedLM

from talkdem.instructions import load_memory_bank
from talkdem.planner import SayCanPlanner
from talkdem.planner.decoding import Generated, clean_generation, cut_loop
from talkdem.planner.strategies import fixed_icl_demonstrations, load_strategy
from talkdem.runs.sampling import select_episodes
from talkdem.schema import PATTERN_CONFIGS, parse_conditions


def test_registry_and_did_you_mean() -> None:
    assert load_strategy("ap").name == "ap"
    with pytest.raises(ValueError, match="did you mean 'tocc'"):
        load_strategy("toc")


def test_ap_adds_the_awareness_sentence_and_vanilla_does_not() -> None:
    lm = ScriptedLM(["done"])
    assert "communication" not in load_strategy("vanilla").prepare(["hi"], lm)[0].preamble
    assert "self-corrections" in load_strategy("ap").prepare(["hi"], lm)[0].preamble


def test_tocc_shows_only_the_rewrite_and_cot_adds_an_interpretation() -> None:
    lm = ScriptedLM(["done"], generated="Put the apple in the fridge")  # the backend has cut at "."
    tocc = load_strategy("tocc").prepare(["um, the, the round thing, in the cold box"], lm)[0]
    assert tocc.instruction == "Put the apple in the fridge." and tocc.notes["rewrite"] == tocc.instruction
    assert tocc.notes["rewrite_status"] == "ok" and tocc.query_label == "Human: "
    cot = load_strategy("cot").prepare(["um, the round thing"], lm)[0]
    assert cot.instruction == "um, the round thing" and cot.interpretation == "Hint: Put the apple in the fridge."
    assert cot.notes["interpretation_status"] == "ok"


def test_an_empty_rewrite_is_recorded_and_never_replaced_by_the_original() -> None:
    original = "um, the round thing, in the cold box"
    for generated in ("", "  \n ", "..."):
        tocc = load_strategy("tocc").prepare([original], ScriptedLM(["done"], generated=generated))[0]
        assert tocc.instruction == "" and tocc.notes["rewrite_status"] == "empty"
        prompt = SayCanPlanner(ScriptedLM(["done"])).prompt_for(tocc)
        assert original not in prompt and prompt.endswith("done.\nHuman:\nRobot: 1.")
        cot = load_strategy("cot").prepare([original], ScriptedLM(["done"], generated=generated))[0]
        assert cot.interpretation == "" and cot.notes["interpretation_status"] == "empty"


def test_tocc_planner_prompt_never_contains_the_original_instruction() -> None:
    # Over a sample of the benchmark (every pattern, level 3), with a model that rewrites to a fixed sentence.
    episodes = select_episodes(
        parse_conditions(
            "clean,referential_imprecision:3,object_substitution:3,empty_speech:3,topic_drift:3,intrusion:3"
        ),
        12,
    )
    lm = ScriptedLM(["done"], generated="Put the apple in the fridge")
    inputs = load_strategy("tocc").prepare([e.text for e in episodes], lm)
    planner = SayCanPlanner(lm)
    for episode, planner_input in zip(episodes, inputs, strict=True):
        prompt = planner.prompt_for(planner_input)
        assert " ".join(episode.text.split()) not in prompt, episode.id
        assert prompt.endswith("Human: Put the apple in the fridge.\nRobot: 1.")


def test_generation_status_cuts_loops_and_flags_the_cap() -> None:
    assert clean_generation("Sure!\nPut the mug in the sink", hit_cap=False) == Generated(
        "Put the mug in the sink.", "ok"
    )
    looped = clean_generation("examine a box, examine a box, examine a box, examine a box, exam", hit_cap=True)
    assert looped == Generated("examine a box", "loop_cut")
    assert clean_generation("There used to be some", hit_cap=True) == Generated("There used to be some", "truncated")
    assert clean_generation(" \n", hit_cap=False).status == "empty"
    assert clean_generation("1", hit_cap=False).status == "empty"  # a numbered plan cut at its first "."
    assert cut_loop("put the the mug away") == ("put the the mug away", False)  # two in a row is not a loop
    assert cut_loop("no no no no") == ("no", True)


def test_decoding_budget_and_stop_rule_reach_the_model() -> None:
    class Asked(ScriptedLM):
        def generate(self, requests):  # type: ignore[no-untyped-def]
            self.requests = list(requests)
            return ["word " * 200]

    lm = Asked(["done"])
    tocc = load_strategy("tocc", max_new_tokens=50)
    result = tocc.prepare(["hi"], lm)[0]
    assert [(r.max_new_tokens, r.stop, r.chat) for r in lm.requests] == [(50, (".", "?", "!"), True)]
    assert result.notes["rewrite_status"] == "loop_cut" and result.instruction == "word"
    assert tocc.options() == {"max_new_tokens": 50, "stop": [".", "?", "!"], "chat": True}
    assert load_strategy("cot", chat=False).options()["chat"] is False


def test_icl_uses_five_fixed_examples_one_per_pattern() -> None:
    memory = load_memory_bank()
    demos = fixed_icl_demonstrations(memory)
    assert len(demos) == 5
    by_text = {m.instruction: m for m in memory}
    assert [by_text[d.instruction].condition.pattern for d in demos] == list(PATTERN_CONFIGS)
    assert len({by_text[d.instruction].task_type for d in demos}) == 5
    assert all(d.interpretation and d.plan[-1] == "done" for d in demos)
