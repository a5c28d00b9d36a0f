"""The multi-sequence llama.cpp scorer on real SayCan steps: its choices against serial scoring, its prefix sharing,
and its memory over many episodes. Needs the `llamacpp` extra (`make test` installs it).

Serial and batched scores of one candidate differ by llama.cpp's batch-layout noise (the same position gives
other values in another batch: up to 0.46 nats per position measured on the default model,
`../shared/design/batching.md`; see `NOISE` for the summed scores of these tests).
So the tests bound the difference by that noise and check choices where the serial scores leave a margin wider
than it, never digits.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from talkdem.llm.backends.llamacpp import LlamaCppLM
from talkdem.llm.interface.requests import ChoiceRequest
from talkdem.planner import PlannerInput, SayCanPlanner
from talkdem.planner.prompt import append_step
from talkdem.skills import vocabulary
from talkdem.tasks import load_tasks

NOISE = 1.0
"""Nats: a bound on llama.cpp's batch-layout noise on one candidate's summed score. Measured between the serial
scorer (float32 KV cache) and 4 sequences in flight over 72 skills x the 4 steps of these tests: with the
multi-sequence scorer's default float16 cache at most 0.67 on SmolLM2-135M (Q4_1) and 0.42 on the default model
(Q4_K_M), with a float32 cache 0.55 and 0.28; the argmax agreed at every step. The bound leaves room for other
CPUs' kernels."""
SKILLS = tuple(" " + skill.text for skill in vocabulary())


def _steps(model: LlamaCppLM, count: int) -> list[str]:
    """Real SayCan contexts: the prompts of `count` benchmark tasks, some after a step or two."""
    planner = SayCanPlanner(model)
    contexts = []
    for index, task in enumerate(load_tasks("benchmark")[:count]):
        context = planner.prompt_for(PlannerInput(task.instruction))
        for step, skill in enumerate(task.reference_plan[: index % 3], start=2):
            context = append_step(context, skill, step)
        contexts.append(context)
    return contexts


@pytest.mark.slow
@pytest.mark.parametrize("name", ["smollm2-135m-instruct", "default"])
def test_batched_choices_agree_with_serial_scoring_within_the_noise(name: str) -> None:
    serial = LlamaCppLM(name, threads=2)
    batched = LlamaCppLM(name, threads=2, sequences=4)
    assert batched.identity.scoring == "sequences-32-f16" and serial.identity.scoring == "chunk-16"
    contexts = _steps(serial, 4)
    candidates = SKILLS[::3]
    found = batched.best_continuations([ChoiceRequest(c, candidates, session=s) for s, c in enumerate(contexts)])
    for context, choice in zip(contexts, found, strict=True):
        scores = serial.score_continuations(context, list(candidates))
        best = max(scores)
        # The batched winner's score is its serial score to within the noise, and no candidate beats it by
        # more than the noise under serial scoring: the choice is serial's own wherever the margin is wider.
        assert abs(choice.score - scores[choice.index]) < NOISE
        assert scores[choice.index] > best - 2 * NOISE
        runner_up = sorted(scores)[-2]
        if best - runner_up > 2 * NOISE:
            assert scores[choice.index] == best
        assert choice.tokens_evaluated > 0  # branch and bound ran expansions, not full scoring
    # The shared few-shot prompt ran once: the other three sequences copied it.
    scorer = batched._sequences
    assert scorer is not None
    assert scorer.tokens_copied >= 3 * 400
    # Asking again for the same steps in other slots gives the same choices (no state leaks between sessions).
    again = batched.best_continuations([ChoiceRequest(c, candidates, session=3 - s) for s, c in enumerate(contexts)])
    assert [a.index for a in again] == [f.index for f in found]


@pytest.mark.slow
def test_memory_stays_bounded_over_a_hundred_episodes() -> None:
    """100 episodes through 4 sequences in a cache too small to hold what they ran in all: if ended episodes
    kept their cells, llama.cpp would run out of KV cells long before the end."""
    model = LlamaCppLM("smollm2-135m-instruct", threads=2, n_ctx=512, sequences=4)
    scorer = model._sequences
    assert scorer is not None and scorer.n_ctx == 1024
    prompt = _steps(model, 1)[0][:600]  # about 150 tokens every episode shares
    options = (" find a mug", " pick up the mug", " done")
    for start in range(0, 100, 4):
        requests = [
            ChoiceRequest(f"{prompt} Episode {e}: put mug number {e * 7919} away, carefully.", options, session=s)
            for s, e in enumerate(range(start, start + 4))
        ]
        model.best_continuations(requests)
        for session in range(4):
            model.end_session(session)
        assert all(not held for held in scorer.held)
    assert scorer.tokens_evaluated > 1024  # more than the cache holds ran through it
    with pytest.raises(ValueError, match="session 4 outside the 4 sequences"):
        model.best_continuations([ChoiceRequest(prompt, options, session=4)])


@pytest.mark.slow
def test_a_batched_run_records_its_layout_and_resumes(tmp_path: Path) -> None:
    """`talkdem run --concurrency 3` on llama.cpp: the header says the multi-sequence layout and the episodes in
    flight; the same command run again finds every episode done; a finished run's records are in selection order."""
    from talkdem.cli import main
    from talkdem.runs import read_episodes, read_header

    out = tmp_path / "run"
    command = ["run", "--backend", "llamacpp", "--model", "smollm2", "--model-arg", "threads=1", "--limit", "2"]
    command += ["--conditions", "clean,intrusion:3", "--max-steps", "3", "--no-progress", "--out", str(out)]
    assert main([*command, "--concurrency", "3"]) == 0
    header = read_header(out)
    assert header.model["scoring"] == "sequences-32-f16"
    assert header.config["backend_args"]["concurrency"] == 3 and header.config["backend_args"]["sequences"] == 3
    first = [e.episode_id for e in read_episodes(out)]
    assert len(first) == 4 and len(set(first)) == 4
    assert main([*command, "--concurrency", "3"]) == 0
    assert [e.episode_id for e in read_episodes(out)] == first


@pytest.mark.slow
def test_the_winner_stays_and_the_next_step_runs_only_what_is_new() -> None:
    """After a choice the sequence holds its context and what it last ran of the winner, never a loser's tokens,
    so a next context that continues with the winner runs only the tokens past what is held. (Branch and bound
    may end on another candidate's expansion, or score a one-token winner from the context's row alone: then
    nothing of the winner is held.)"""
    model = LlamaCppLM("smollm2-135m-instruct", threads=1, sequences=2)
    scorer = model._sequences
    assert scorer is not None
    options = [model.encode(c) for c in SKILLS[::3]]
    kept_any = False
    for text in _steps(model, 4):
        context = model.context_ids(text)
        [choice] = scorer.best([0], [context], [options])
        winner, held = options[choice.index], list(scorer.held[0])
        assert held[: len(context)] == context
        kept = held[len(context) :]
        assert kept == winner[: len(kept)], "the sequence keeps the winner's tokens, and only those"
        kept_any |= bool(kept)
        following = context + winner + model.encode("\n")
        before = scorer.tokens_evaluated
        [second] = scorer.best([0], [following], [options])
        assert scorer.tokens_evaluated - before == len(following) - len(held) + second.tokens_evaluated
    assert kept_any, "on none of the steps did the sequence keep any of the winner"
