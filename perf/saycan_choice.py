"""The SayCan choice on the default model (Qwen2.5-Coder-0.5B, llama.cpp, 2 threads): three ways, side by side.

At every step the planner needs the best of the 214 vocabulary skills given the prompt. Measured on the same
real steps (a stratified benchmark task's prompt, then the prompt after each of its first reference steps):
- branch and bound: best-first over the skills' token trie, stops at the first complete skill (exact);
- full trie: every skill scored, shared beginnings (" pick up the") run once;
- one pass per skill: every skill's tokens run on their own after the cached prompt.
Each step's time includes bringing the prompt up to date (a few new tokens after the first step). The first
step of an episode (the whole prompt runs) is reported apart. The load average is printed because the
machine may be shared.
"""

from __future__ import annotations

import os
import statistics
import time
from collections.abc import Callable, Sequence

THREADS = 2
STEPS = 5
"""The prompt, then after each of the first four reference steps."""
PER_SKILL_STEPS = 2
GOAL_SECONDS = 1.5


def _contexts(model: object) -> list[str]:
    from talkdem.planner import PlannerInput, SayCanPlanner
    from talkdem.planner.prompt import append_step
    from talkdem.tasks import load_tasks

    task = load_tasks("benchmark")[0]
    context = SayCanPlanner(model).prompt_for(PlannerInput(task.instruction))  # type: ignore[arg-type]
    contexts = [context]
    for step, skill in enumerate(task.reference_plan[: STEPS - 1], start=2):
        context = append_step(context, skill, step)
        contexts.append(context)
    return contexts


def _episode(
    model: object, contexts: Sequence[str], choose: Callable[[str], int]
) -> tuple[list[float], list[int], list[int]]:
    """Per-step seconds, tokens run and choices, from a cold context (as at an episode's start)."""
    model.forget_context()  # type: ignore[attr-defined]
    seconds, tokens, choices = [], [], []
    for context in contexts:
        before = model.tokens_evaluated  # type: ignore[attr-defined]
        start = time.perf_counter()
        choices.append(choose(context))
        seconds.append(time.perf_counter() - start)
        tokens.append(model.tokens_evaluated - before)  # type: ignore[attr-defined]
    return seconds, tokens, choices


def main() -> None:
    try:
        from talkdem.llm.backends.llamacpp import LlamaCppLM
    except ImportError as error:
        print(f"saycan choice: skipped ({error})")
        return
    from talkdem.llm.interface.models import DEFAULT_MODEL
    from talkdem.skills import vocabulary

    model = LlamaCppLM(DEFAULT_MODEL, threads=THREADS)
    skills = [" " + skill.text for skill in vocabulary()]
    tokenized = [model.encode(s) for s in skills]
    contexts = _contexts(model)
    load_before = os.getloadavg()[0]

    def argmax(scores: list[float]) -> int:
        return max(range(len(scores)), key=lambda i: (scores[i], -i))

    def branch_and_bound(context: str) -> int:
        return model.best_token_continuation(model.context_ids(context), tokenized).index

    def full_trie(context: str) -> int:
        return argmax(model.score_token_continuations(model.context_ids(context), tokenized))

    def per_skill(context: str) -> int:
        return argmax(model.score_token_continuations(model.context_ids(context), tokenized, share_prefixes=False))

    runs = {
        "branch and bound": _episode(model, contexts, branch_and_bound),
        "full trie": _episode(model, contexts, full_trie),
        "one pass per skill": _episode(model, contexts[:PER_SKILL_STEPS], per_skill),
    }
    load_after = os.getloadavg()[0]
    prompt_tokens = len(model.context_ids(contexts[0]))
    print(
        f"{DEFAULT_MODEL} (Q4_K_M, llama.cpp, {THREADS} threads): {len(skills)} skills "
        f"({sum(len(t) for t in tokenized)} tokens), prompt {prompt_tokens} tokens; "
        f"load average {load_before:.1f} -> {load_after:.1f} on {os.cpu_count()} CPUs"
    )
    reference = runs["branch and bound"]
    bnb_next = statistics.mean(reference[0][1:])
    for label, (seconds, tokens, choices) in runs.items():
        later = seconds[1:]
        next_mean = statistics.mean(later)
        same = sum(a == b for a, b in zip(choices, reference[2], strict=False))
        print(
            f"  {label:<19} next steps {next_mean:5.2f} s/step ({statistics.mean(tokens[1:]):6.0f} tokens), "
            f"first step {seconds[0]:5.2f} s ({tokens[0]} tokens); x{next_mean / bnb_next:.1f} vs branch and bound; "
            f"same choice as branch and bound on {same}/{len(choices)} steps"
        )
    verdict = "met" if bnb_next <= GOAL_SECONDS else "NOT met"
    print(f"  goal <= {GOAL_SECONDS} s per step (after the first) with branch and bound: {verdict}")


if __name__ == "__main__":
    main()
