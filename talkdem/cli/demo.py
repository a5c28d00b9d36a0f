"""`talkdem demo`: the main job on its embedded defaults (what `make demo` runs).

1. The diversity table of the task selection (saved with the data).
2. The SayCan planner on the embedded default model (SmolLM2-135M-Instruct, CPU) under Vanilla and CARE
   on a stratified sample: every pattern and level plus the clean control, for the same `--tasks` tasks.
   Runs resume: a second `make demo` only scores.
3. The reference plans of the same episodes as an oracle row.
4. Scores, the paper's tables, plots and a leaderboard page.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path
from typing import Any

from talkdem.cli.arguments import positive_int

__all__ = ["register"]


def register(subparsers: Any) -> None:
    parser = subparsers.add_parser("demo", help="run the main job on its embedded defaults (make demo)")
    parser.add_argument(
        "--tasks", type=positive_int, default=1, help="tasks in the sample; each runs under all 16 conditions"
    )
    parser.add_argument("--strategies", default="vanilla,care", help="comma-separated strategies")
    parser.add_argument("--out", type=Path, default=Path("demo_output"), help="folder for runs, report, leaderboard")
    parser.add_argument("--threads", type=positive_int, default=2)
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    from builders.selection import format_diversity_table, load_diversity
    from talkdem.leaderboard import write_leaderboard
    from talkdem.llm.default_model import DEFAULT_MODEL_NAME
    from talkdem.llm.registry import load_model
    from talkdem.planner.saycan import SayCanConfig
    from talkdem.planner.strategies import load_strategy
    from talkdem.report import score_runs, write_report
    from talkdem.runs.oracle import write_oracle_run
    from talkdem.runs.runner import run_episodes
    from talkdem.runs.sampling import select_episodes
    from talkdem.schema import CONDITIONS

    started = time.perf_counter()
    print("== 1. Task selection: mean pairwise MiniLM similarity (lower = more diverse) ==")
    print(format_diversity_table(load_diversity()))

    episodes = select_episodes(CONDITIONS, args.tasks)
    strategies = [s.strip() for s in args.strategies.split(",") if s.strip()]
    print(
        f"\n== 2. SayCan with {DEFAULT_MODEL_NAME} on {len(episodes)} episodes per strategy "
        f"({args.tasks} task(s) x {len(CONDITIONS)} conditions): {', '.join(strategies)} =="
    )
    model = load_model("hf", DEFAULT_MODEL_NAME, threads=args.threads)
    run_dirs = []
    for name in strategies:
        run_dir = args.out / "runs" / f"{DEFAULT_MODEL_NAME}-{name}"
        summary = run_episodes(
            episodes,
            model,
            load_strategy(name),
            run_dir,
            SayCanConfig(),
            extra_config={"conditions": "all", "tasks": args.tasks},
        )
        print(f"{name}: {summary.ran} run, {summary.skipped} resumed -> {run_dir}")
        run_dirs.append(run_dir)

    oracle_dir = args.out / "runs" / "oracle"
    write_oracle_run(episodes, oracle_dir)
    run_dirs.append(oracle_dir)

    print("\n== 3. Scores ==")
    runs = score_runs(run_dirs, bootstrap=200)
    files = write_report(runs, args.out / "report", reference_strategy="CARE")
    for table in files.tables:
        print(table.to_markdown())
        print()
    pages = write_leaderboard(runs, args.out / "leaderboard")
    print(f"report:      {files.markdown}")
    print(f"plots:       {', '.join(str(p) for p in files.plots)}")
    print(f"leaderboard: {next((p for p in pages if p.suffix == '.html'), pages[0])}")
    print(f"runs:        {', '.join(str(d) for d in run_dirs)}")
    print(f"done in {time.perf_counter() - started:.0f} s")
    return 0
