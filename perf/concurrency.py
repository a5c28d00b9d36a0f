"""Episodes in flight: the same episodes serially (`--concurrency 1`) and batched (`--concurrency 8`), side by side.

Per strategy, in this one process (1 llama.cpp thread, the default model, SayCan sum scoring with failure messages
as the committed runs): the 12 episodes of issue 47 (the first 3 tasks of the stratified order x clean,
referential imprecision level 3, object substitution level 2, intrusion level 3) run once serially on the
fixed-chunk scorer and once with 8 episodes in flight on the multi-sequence scorer. It prints episodes per hour,
tokens run per episode, milliseconds per token, how many tokens prefix sharing copied instead of running, the
share of steps with the same choice on a shared history (steps up to and including each episode's first
difference), the episodes whose outcome differs, and the projection for the 4,800 episodes on two processes.

`TALKDEM_BENCH_STRATEGIES=vanilla,care` limits the strategies (all six take about half an hour on 2 cores).
`TALKDEM_BENCH_KV=f32,f16` runs the batched side once per KV cache type (default: f16, the multi-sequence
scorer's default; f32 is the serial scorer's).
The 12-episode set ends with a few long episodes in flight alone (the longest runs 30 steps), so its speed-up is
lower than a long run's, where 8 episodes are always in flight; `TALKDEM_BENCH_TASKS` widens it.
"""

from __future__ import annotations

import json
import os
import tempfile
import time
from pathlib import Path
from typing import Any

THREADS = 1
CONCURRENCY = 8
CONDITIONS = "clean,referential_imprecision:3,object_substitution:2,intrusion:3"
BENCHMARK_EPISODES = 4800
PROCESSES = 2
STRATEGY_OPTIONS: dict[str, dict[str, object]] = {"care": {"order": "best_last"}}


def shared_history_agreement(serial: dict[str, Any], batched: dict[str, Any]) -> tuple[int, int, int]:
    """(steps with the same choice, steps both runs took on a shared history, episodes whose outcome differs)."""
    same = compared = outcomes = 0
    for episode_id, record in serial.items():
        a, b = record["plan"], batched[episode_id]["plan"]
        agree = 0
        while agree < min(len(a), len(b)) and a[agree] == b[agree]:
            agree += 1
        same += agree
        compared += min(agree + 1, len(a), len(b))
        outcomes += record["success"] != batched[episode_id]["success"]
    return same, compared, outcomes


def _run(model: Any, episodes: Any, strategy: Any, folder: Path, concurrency: int) -> tuple[float, dict[str, Any]]:
    from talkdem.planner.saycan import SayCanConfig
    from talkdem.runs.runner import run_episodes

    start = time.perf_counter()
    run_episodes(
        episodes,
        model,
        strategy,
        folder,
        config=SayCanConfig.with_feedback("message"),
        progress=False,
        concurrency=concurrency,
    )
    wall = time.perf_counter() - start
    records = [json.loads(line) for line in (folder / "episodes.jsonl").read_text().splitlines()]
    return wall, {r["episode_id"]: r for r in records}


def main() -> None:
    try:
        from talkdem.llm.backends.llamacpp import LlamaCppLM
    except ImportError as error:
        print(f"concurrency: skipped ({error})")
        return
    os.environ.setdefault("HF_HUB_OFFLINE", "1")
    from talkdem.llm.interface.models import DEFAULT_MODEL
    from talkdem.planner.strategies import STRATEGIES, load_strategy
    from talkdem.runs.sampling import select_episodes
    from talkdem.schema import parse_conditions

    tasks = int(os.environ.get("TALKDEM_BENCH_TASKS", "3"))
    names = [n for n in os.environ.get("TALKDEM_BENCH_STRATEGIES", ",".join(STRATEGIES.names())).split(",") if n]
    episodes = select_episodes(parse_conditions(CONDITIONS), tasks)
    serial_model = LlamaCppLM(DEFAULT_MODEL, threads=THREADS)
    kv_types = [k for k in os.environ.get("TALKDEM_BENCH_KV", "f16").split(",") if k]
    batched_models = {
        kv: LlamaCppLM(DEFAULT_MODEL, threads=THREADS, sequences=CONCURRENCY, f32_kv_cache=kv == "f32")
        for kv in kv_types
    }
    print(
        f"{DEFAULT_MODEL} (Q4_K_M, llama.cpp, {THREADS} thread): {len(episodes)} episodes per strategy "
        f"({tasks} tasks x {CONDITIONS}); --concurrency 1 ({serial_model.identity.scoring}) against "
        f"--concurrency {CONCURRENCY} ({', '.join(m.identity.scoring for m in batched_models.values())}); "
        f"load average {os.getloadavg()[0]:.1f} "
        f"on {os.cpu_count()} CPUs"
    )
    with tempfile.TemporaryDirectory() as folder:
        for name in names:
            strategy = load_strategy(name, **STRATEGY_OPTIONS.get(name, {}))
            serial_model.forget_context()
            before = serial_model.tokens_evaluated
            serial_wall, serial = _run(serial_model, episodes, strategy, Path(folder) / f"{name}-1", 1)
            serial_tokens = serial_model.tokens_evaluated - before
            count = len(episodes)
            _print_speed(name, "serial", serial_wall, serial_tokens, count)
            for kv, batched_model in batched_models.items():
                scorer = batched_model._sequences
                assert scorer is not None
                before, copied = scorer.tokens_evaluated, scorer.tokens_copied
                folder_name = Path(folder) / f"{name}-8-{kv}"
                batched_wall, batched = _run(batched_model, episodes, strategy, folder_name, CONCURRENCY)
                _print_speed(name, f"batched-{kv}", batched_wall, scorer.tokens_evaluated - before, count)
                same, compared, outcomes = shared_history_agreement(serial, batched)
                print(
                    f"  {name:<8} {kv} speed-up x{serial_wall / batched_wall:.2f}; prefix sharing copied "
                    f"{(scorer.tokens_copied - copied) / count:.0f} tokens/episode; same choice at {same}/{compared} "
                    f"steps on a shared history ({100 * same / max(compared, 1):.1f}%); outcome differs in "
                    f"{outcomes}/{count} episodes"
                )


def _print_speed(name: str, label: str, wall: float, tokens: int, count: int) -> None:
    hours = BENCHMARK_EPISODES * wall / count / PROCESSES / 3600
    print(
        f"  {name:<8} {label:<11} {3600 * count / wall:6.0f} episodes/h, "
        f"{tokens / count:5.0f} tokens/episode, {1000 * wall / max(tokens, 1):5.1f} ms/token; "
        f"{BENCHMARK_EPISODES} episodes on {PROCESSES} processes: {hours:4.1f} h"
    )


if __name__ == "__main__":
    main()
