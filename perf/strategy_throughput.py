"""Episodes per hour per strategy on the default model, side by side, and where each strategy's time goes.

The six strategies run the same episodes (the first tasks of the stratified order, each as the clean control
and level 3 of two patterns) one after the other in this process, with the settings of the committed runs
(Qwen2.5-Coder-0.5B Q4_K_M on llama.cpp, 1 thread, SayCan sum scoring with branch and bound, failure messages
shown). Per strategy it prints the seconds per episode, how many of them went to preparing the prompts (CARE's
retrieval, TOCC's rewriting, CoT's hint) and to planning, the tokens llama.cpp ran for scoring per episode and per step,
and the hours the 4,800-episode benchmark would take with two such processes on two cores (the issue's goal is
2 hours for Vanilla and CARE). The projection assumes two processes each keep the rate measured here for one;
on a machine shared with other work they do not, so the load average is printed beside it.
"""

from __future__ import annotations

import json
import os
import statistics
import tempfile
import time
from pathlib import Path

THREADS = 1
TASKS = 2
CONDITIONS = "clean,referential_imprecision:3,intrusion:3"
BENCHMARK_EPISODES = 4800
PROCESSES = 2
GOAL_HOURS = 2.0
STRATEGY_OPTIONS: dict[str, dict[str, object]] = {"care": {"order": "best_last"}}
"""CARE's most similar item next to the query, as `talkdem run` and the committed runs use it."""


def main() -> None:
    try:
        from talkdem.llm.backends.llamacpp import LlamaCppLM
    except ImportError as error:
        print(f"strategy throughput: skipped ({error})")
        return
    os.environ.setdefault("HF_HUB_OFFLINE", "1")
    from talkdem.llm.interface.models import DEFAULT_MODEL
    from talkdem.planner.saycan import SayCanConfig
    from talkdem.planner.strategies import STRATEGIES, load_strategy
    from talkdem.runs.runner import run_episodes
    from talkdem.runs.sampling import select_episodes
    from talkdem.schema import parse_conditions

    model = LlamaCppLM(DEFAULT_MODEL, threads=THREADS)
    episodes = select_episodes(parse_conditions(CONDITIONS), TASKS)
    config = SayCanConfig.with_feedback("message")
    load_before = os.getloadavg()[0]
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        for name in STRATEGIES.names():
            strategy = load_strategy(name, **STRATEGY_OPTIONS.get(name, {}))
            model.forget_context()  # every strategy starts cold, as a new process would
            tokens_before = model.tokens_evaluated
            start = time.perf_counter()
            run_dir = Path(folder) / name
            run_episodes(episodes, model, strategy, run_dir, config=config, progress=False)
            wall = time.perf_counter() - start
            records = [json.loads(line) for line in (run_dir / "episodes.jsonl").read_text().splitlines()]
            planning = sum(float(r["timing"]["planning_seconds"]) for r in records)
            steps = sum(len(r["plan"]) for r in records)
            tokens = model.tokens_evaluated - tokens_before
            rows.append((name, len(records), wall, planning, steps, tokens))
    load_after = os.getloadavg()[0]
    print(
        f"{DEFAULT_MODEL} (Q4_K_M, llama.cpp, {THREADS} thread): {len(episodes)} episodes per strategy "
        f"({TASKS} tasks x {CONDITIONS}); load average {load_before:.1f} -> {load_after:.1f} on "
        f"{os.cpu_count()} CPUs"
    )
    vanilla_seconds = next(wall / count for name, count, wall, *_ in rows if name == "vanilla")
    for name, count, wall, planning, steps, tokens in rows:
        per_episode = wall / count
        hours = BENCHMARK_EPISODES * per_episode / PROCESSES / 3600
        verdict = ("met" if hours <= GOAL_HOURS else "NOT met") if name in ("vanilla", "care") else ""
        print(
            f"  {name:<8} {per_episode:6.2f} s/episode (x{per_episode / vanilla_seconds:.1f} vs vanilla; "
            f"prepare {(wall - planning) / count:5.2f} s, plan {planning / count:5.2f} s), "
            f"{3600 / per_episode:5.0f} episodes/h, {tokens / count:5.0f} tokens/episode "
            f"({tokens / max(steps, 1):4.1f}/step, {steps / count:4.1f} steps), "
            f"{BENCHMARK_EPISODES} episodes on {PROCESSES} processes: {hours:4.1f} h {verdict}".rstrip()
        )
    per_token = statistics.mean(planning / max(tokens, 1) for _, _, _, planning, _, tokens in rows)
    print(
        f"  planning: about {per_token * 1000:.0f} ms per scored token (mean over strategies), so planning time "
        "follows the tokens run; tokens are the scoring passes' (prompt and candidates), not TOCC's or CoT's "
        "generated text, which is part of 'prepare'"
    )


if __name__ == "__main__":
    main()
