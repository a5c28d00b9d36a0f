"""The fast SayCan scorer against the naive one, on the real default model (SmolLM2-135M)."""

from __future__ import annotations

import pytest

from talkdem.llm.backends.hf import HFCausalLM
from talkdem.llm.interface.requests import LoglikelihoodRequest
from talkdem.llm.scoring.prefix_scorer import PrefixCachedScorer
from talkdem.skills import vocabulary

PROMPT = (
    "Robot: Hi there, I'm a robot operating in a house.\n"
    "Robot: You can ask me to do various tasks and I'm gonna tell you the sequence of actions I would do.\n"
    "Human pending instruction: Could you put a washed apple on the dining table?\n"
    "Robot: 1. find an apple, 2. pick up the apple, 3. find a sink, 4. put down the apple, 5. find a faucet, "
    "6. turn on the faucet, 7. turn off the faucet, 8. find an apple, 9. pick up the apple, 10. find a dining "
    "table, 11. put down the apple, 12. done.\n"
    "Human pending instruction: Oh, the, um, the thing, the mug, could you warm it up and leave it on the counter?\n"
    "Robot: 1."
)
SKILLS = [" " + skill.text for skill in vocabulary()]
SAMPLE = SKILLS[::19]  # 12 candidates across every verb: the naive scorer costs a full pass each


@pytest.fixture(scope="module")
def smollm() -> HFCausalLM:
    return HFCausalLM("smollm2-135m-instruct", threads=2)


@pytest.mark.slow
def test_fast_and_naive_scores_agree(smollm: HFCausalLM) -> None:
    fast = smollm.score_continuations(PROMPT, SKILLS)
    naive = smollm.naive_score_continuations(PROMPT, SAMPLE)
    sampled_fast = [fast[SKILLS.index(c)] for c in SAMPLE]
    assert max(abs(a - b) for a, b in zip(sampled_fast, naive, strict=True)) < 1e-3
    assert max(range(len(SAMPLE)), key=lambda i: naive[i]) == max(range(len(SAMPLE)), key=lambda i: sampled_fast[i])
    assert len({round(s, 3) for s in fast}) > 100, "candidate scores must differ"


@pytest.mark.slow
def test_reused_prefix_cache_gives_fresh_scores(smollm: HFCausalLM) -> None:
    smollm.score_continuations(PROMPT, SAMPLE)
    stepped = smollm.score_continuations(PROMPT + " find a mug, 2.", SAMPLE)
    # A different earlier context forces the cache to roll back to the shared part.
    smollm.score_continuations(PROMPT.replace("warm it up", "chill it"), SAMPLE)
    again = smollm.score_continuations(PROMPT + " find a mug, 2.", SAMPLE)
    fresh = PrefixCachedScorer(smollm.model).score(
        smollm._context_ids(PROMPT + " find a mug, 2."), [smollm.encode(c) for c in SAMPLE]
    )
    assert stepped == pytest.approx(fresh, abs=1e-4)
    assert again == pytest.approx(fresh, abs=1e-4)


@pytest.mark.slow
def test_small_packing_budget_splits_into_chunks_with_equal_scores(smollm: HFCausalLM) -> None:
    chunked = PrefixCachedScorer(smollm.model, max_packed_tokens=16)
    one_pass = PrefixCachedScorer(smollm.model)
    ids = smollm._context_ids(PROMPT)
    candidates = [smollm.encode(c) for c in SKILLS[:60]]
    assert chunked.score(ids, candidates) == pytest.approx(one_pass.score(ids, candidates), abs=1e-4)


@pytest.mark.slow
def test_loglikelihood_requests_keep_their_order(smollm: HFCausalLM) -> None:
    requests = [
        LoglikelihoodRequest(PROMPT, " find a mug"),
        LoglikelihoodRequest("Human: hello\nRobot:", " hi"),
        LoglikelihoodRequest(PROMPT, " done"),
    ]
    scores = smollm.loglikelihood(requests)
    direct = smollm.score_continuations(PROMPT, [" find a mug", " done"])
    assert scores[0] == pytest.approx(direct[0], abs=1e-4) and scores[2] == pytest.approx(direct[1], abs=1e-4)
    assert scores[1] < 0
