"""Scoring every skill on the transformers backend (SmolLM2-135M, CPU): packed scorer vs naive scorer.

Per SayCan step every one of the 214 vocabulary skills is scored given a real planner prompt (a benchmark
task's instruction with the six task-type examples). Measured side by side in one run:
- fast, first call: the prompt runs from scratch, then all candidates in one packed pass;
- fast, next step: the prompt plus one executed step (a few new tokens over the cached prefix);
- naive: one full forward pass of prompt + skill per candidate, timed on a spread sample and extrapolated
  to 214 (a full naive step takes minutes).
The default model on llama.cpp (branch and bound vs full scoring) is in `saycan_choice`; CARE's retrieval
in `care_retrieval`.
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from talkdem.llm.interface.base import LanguageModel

NAIVE_SAMPLE = 6
THREADS = 2

Scorer = Callable[[str, Sequence[str]], list[float]]


def _timed(function: Callable[[], object]) -> float:
    start = time.perf_counter()
    function()
    return time.perf_counter() - start


def _planner_prompt(model: LanguageModel) -> tuple[str, str]:
    """A real planner prompt for the first benchmark task, and the prompt one step later."""
    from talkdem.planner import PlannerInput, SayCanPlanner
    from talkdem.planner.prompt import append_step
    from talkdem.tasks import load_tasks

    task = load_tasks("benchmark")[0]
    prompt = SayCanPlanner(model).prompt_for(PlannerInput(task.instruction))
    return prompt, append_step(prompt, task.reference_plan[0], 2)


def _compare(
    label: str, fast: Scorer, naive: Scorer, prompt: str, next_prompt: str, skills: list[str], naive_sample: int
) -> None:
    candidates = [" " + skill for skill in skills]
    first = _timed(lambda: fast(prompt, candidates))
    step = _timed(lambda: fast(next_prompt, candidates))
    sample = candidates[:: max(1, len(candidates) // naive_sample)][:naive_sample]
    naive_step = _timed(lambda: naive(next_prompt, sample)) / len(sample) * len(candidates)
    print(
        f"{label}: {len(candidates)} candidates per step; fast {step:.2f} s/step "
        f"(first call of an episode {first:.2f} s); naive {naive_step:.1f} s/step "
        f"(extrapolated from {len(sample)} candidates); speed-up {naive_step / step:.0f}x per step, "
        f"{naive_step / first:.0f}x on the first call (target: >= 30x and < 2 s/step on 2 cores)"
    )


def _hf_scoring(skills: list[str]) -> None:
    from talkdem.llm.backends.hf import HFCausalLM

    load = time.perf_counter()
    model = HFCausalLM("smollm2-135m-instruct", threads=THREADS)
    prompt, next_prompt = _planner_prompt(model)
    print(
        f"hf (transformers, fp32, {THREADS} threads): loaded in {time.perf_counter() - load:.1f} s; "
        f"prompt {len(model._context_ids(prompt))} tokens"
    )
    _compare(
        "hf", model.score_continuations, model.naive_score_continuations, prompt, next_prompt, skills, NAIVE_SAMPLE
    )


def main() -> None:
    os.environ.setdefault("HF_HUB_OFFLINE", "1")
    os.environ.setdefault("TOKENIZERS_PARALLELISM", "false")
    from talkdem.skills import vocabulary

    skills = [skill.text for skill in vocabulary()]
    _hf_scoring(skills)


if __name__ == "__main__":
    main()
