"""The llama.cpp backend on the embedded SmolLM2-135M GGUF: its scores against the HF backend's and against its
own naive scorer, on a real SayCan prompt. Needs the `llamacpp` extra (`make test` installs it).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.stats import spearmanr

from talkdem.llm.backends.hf import HFCausalLM
from talkdem.llm.backends.llamacpp import LlamaCppLM
from talkdem.llm.interface.requests import GenerateRequest, LoglikelihoodRequest
from talkdem.planner import PlannerInput, SayCanPlanner
from talkdem.planner.prompt import append_step
from talkdem.skills import vocabulary
from talkdem.tasks import load_tasks

SKILLS = [" " + skill.text for skill in vocabulary()]
SAMPLE = SKILLS[::54]  # 4 candidates across the verbs: the naive scorer runs the whole prompt for each


@pytest.fixture(scope="module")
def llama() -> LlamaCppLM:
    return LlamaCppLM("smollm2-135m-instruct", threads=2)


@pytest.fixture(scope="module")
def hf() -> HFCausalLM:
    return HFCausalLM("smollm2-135m-instruct", threads=2)


@pytest.fixture(scope="module")
def saycan_prompt(llama: LlamaCppLM) -> str:
    task = load_tasks("benchmark")[0]
    return SayCanPlanner(llama).prompt_for(PlannerInput(task.instruction))


def _argmax(scores: list[float]) -> int:
    return max(range(len(scores)), key=lambda i: scores[i])


@pytest.mark.slow
def test_scores_agree_with_the_hf_backend(llama: LlamaCppLM, hf: HFCausalLM, saycan_prompt: str) -> None:
    # Not bit-equal: llama.cpp multiplies Q4_1 weights with activations quantized to 8 bits, the HF backend
    # de-quantizes the same weights to float32. Measured on three SayCan prompts: mean |difference| 0.10-0.24
    # nats, worst 0.37-0.66, Spearman rank correlation over the 214 skills >= 0.999.
    assert llama.context_ids(saycan_prompt) == hf._context_ids(saycan_prompt), "the same tokenization"
    ours = np.array(llama.score_continuations(saycan_prompt, SKILLS))
    theirs = np.array(hf.score_continuations(saycan_prompt, SKILLS))
    difference = np.abs(ours - theirs)
    assert difference.mean() < 0.4 and difference.max() < 1.0, (
        f"mean {difference.mean():.3f}, worst {difference.max():.3f}"
    )
    assert spearmanr(ours, theirs).statistic > 0.995
    assert int(theirs.argmax()) in set(np.argsort(-ours)[:3].tolist()), "HF's choice is among llama.cpp's top 3"
    assert len({round(float(s), 3) for s in ours}) > 100, "candidate scores must differ"


@pytest.mark.slow
def test_fast_and_naive_scores_agree(llama: LlamaCppLM, saycan_prompt: str) -> None:
    context = append_step(saycan_prompt, SKILLS[0].strip(), 2)
    fast = llama.score_continuations(context, SKILLS)
    naive = llama.naive_score_continuations(context, SAMPLE)
    sampled_fast = [fast[SKILLS.index(c)] for c in SAMPLE]
    assert max(abs(a - b) for a, b in zip(sampled_fast, naive, strict=True)) < 1e-3
    assert _argmax(sampled_fast) == _argmax(naive)


@pytest.mark.slow
def test_reused_prefix_gives_fresh_scores(llama: LlamaCppLM, saycan_prompt: str) -> None:
    stepped_context = append_step(saycan_prompt, "find a mug", 2)
    llama.score_continuations(saycan_prompt, SAMPLE)
    stepped = llama.score_continuations(stepped_context, SAMPLE)
    # A different earlier context forces the context to roll back to the shared part.
    llama.score_continuations(saycan_prompt.replace("Robot:", "Robot :", 1), SAMPLE)
    again = llama.score_continuations(stepped_context, SAMPLE)
    fresh = LlamaCppLM("smollm2-135m-instruct", threads=2).score_continuations(stepped_context, SAMPLE)
    assert stepped == pytest.approx(fresh, abs=1e-3)
    assert again == pytest.approx(fresh, abs=1e-3)


@pytest.mark.slow
def test_loglikelihood_requests_keep_their_order(llama: LlamaCppLM, saycan_prompt: str) -> None:
    requests = [
        LoglikelihoodRequest(saycan_prompt, " find a mug"),
        LoglikelihoodRequest("Human: hello\nRobot:", " hi"),
        LoglikelihoodRequest(saycan_prompt, " done"),
    ]
    scores = llama.loglikelihood(requests)
    direct = llama.score_continuations(saycan_prompt, [" find a mug", " done"])
    assert scores[0] == pytest.approx(direct[0], abs=1e-4) and scores[2] == pytest.approx(direct[1], abs=1e-4)
    assert scores[1] < 0


@pytest.mark.slow
def test_greedy_generation_is_deterministic_and_scoring_still_right_after_it(
    llama: LlamaCppLM, saycan_prompt: str
) -> None:
    before = llama.score_continuations(saycan_prompt, SAMPLE)
    held = llama._llm.n_tokens
    request = GenerateRequest(saycan_prompt + " ", max_new_tokens=16, stop=(",", "\n"))
    first = llama.generate([request])
    assert first == llama.generate([request]) and first[0] and "," not in first[0]
    # Generation runs in its own context: the scoring context still holds the prompt for the next call.
    assert llama._llm.n_tokens == held > 0 and llama._generator is not None
    assert llama.score_continuations(saycan_prompt, SAMPLE) == pytest.approx(before, abs=1e-3)


@pytest.mark.slow
def test_generation_does_not_depend_on_the_request_before(llama: LlamaCppLM, saycan_prompt: str) -> None:
    """The generation context starts each request from an empty cache, so a request generates the same text
    after another one as in a fresh model (a sharded or resumed run generates what a serial run does)."""
    request = GenerateRequest(saycan_prompt + " ", max_new_tokens=16, stop=(",", "\n"))
    fresh = LlamaCppLM("smollm2-135m-instruct", threads=2).generate([request])
    llama.generate([GenerateRequest(saycan_prompt[: len(saycan_prompt) // 2], max_new_tokens=8)])
    assert llama.generate([request]) == fresh


@pytest.mark.slow
def test_identity_names_the_weights(llama: LlamaCppLM, hf: HFCausalLM) -> None:
    assert llama.identity.backend == "llamacpp"
    assert llama.identity.revision == hf.identity.revision and len(llama.identity.revision) == 64


def test_missing_llama_cpp_names_the_extra(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "llama_cpp", None)  # its import now fails, installed or not
    with pytest.raises(ImportError, match=r"\[llamacpp\]"):
        LlamaCppLM("default")


def test_a_run_records_its_thread_count(tmp_path: Path) -> None:
    # llama.cpp's results can move with the thread count, so a run header must say which one computed it.
    from talkdem.cli import main
    from talkdem.runs import read_header

    out = tmp_path / "run"
    command = ["run", "--backend", "llamacpp", "--model", "smollm2", "--model-arg", "threads=1"]
    command += ["--conditions", "clean"]
    assert main([*command, "--limit", "1", "--max-steps", "1", "--no-progress", "--out", str(out)]) == 0
    header = read_header(out)
    assert header.config["threads"] == 1
    # ... and the build that computed it: llama-cpp-python is compiled on each machine for its CPU's features.
    import llama_cpp

    (runtime,) = header.runtimes
    assert runtime["llama_cpp_python"] == llama_cpp.__version__
    assert runtime["llama_cpp_system_info"].startswith("CPU :")


@pytest.mark.slow
def test_default_model_scores_do_not_depend_on_what_the_cache_held() -> None:
    """What makes a sharded or resumed run score as a serial one: on the default model (Q4_K_M) llama.cpp's
    scores move with the batch a candidate runs in (a from-scratch pass with the prompt differs from the
    prefix-reusing one by up to 0.3 nats, measured), so the backend must at least give a step the same scores
    whatever the cache held before: a fresh model, one that held another prompt, one that held the previous
    step (measured equal to the last bit on this project's machine)."""
    model = LlamaCppLM("default", threads=2)
    task = load_tasks("benchmark")[1]
    prompt = SayCanPlanner(model).prompt_for(PlannerInput(task.instruction))
    step = append_step(prompt, "find a mug", 1)
    skills = SKILLS[::5]
    fresh = model.score_continuations(step, skills)
    model.forget_context()
    model.score_continuations(prompt.replace(task.instruction, "Bring me the thing, you know."), SAMPLE)
    after_other = model.score_continuations(step, skills)
    model.forget_context()
    model.score_continuations(prompt, SAMPLE)
    after_previous = model.score_continuations(step, skills)
    for scores in (after_other, after_previous):
        assert max(abs(a - b) for a, b in zip(scores, fresh, strict=True)) < 1e-3
        assert _argmax(scores) == _argmax(fresh)


def test_the_context_layout_is_fixed_chunks_without_a_one_token_batch() -> None:
    model = LlamaCppLM("smollm2-135m-instruct", threads=1, context_chunk=4)
    assert [model._chunks(n) for n in (1, 3, 8, 9, 10)] == [[0, 1], [0, 3], [0, 4, 8], [0, 4, 9], [0, 4, 8, 10]]
    assert model.identity.scoring == "chunk-4" and model.identity.key().endswith("+chunk-4")
    with pytest.raises(ValueError, match="context_chunk must be between 2 and n_batch - 1"):
        LlamaCppLM("smollm2-135m-instruct", context_chunk=512)
