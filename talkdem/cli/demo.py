"""`talkdem demo`: the main job on its defaults, live, in about ten minutes on 2 cores (what `make demo` runs).

1. The diversity table of the task selection (saved with the data).
2. The SayCan planner on the default model (Qwen2.5-Coder-0.5B-Instruct, llama.cpp, CPU) under Vanilla and
   CARE on a small sample: the first `--tasks` tasks of the stratified order (round robin over the task
   types; the same order a limited `talkdem run` uses, not picked for success), each as the clean control
   and every pattern at one level. Runs resume: a second `make demo` only scores.
3. The reference plans of the same episodes as an oracle row.
4. Scores, the paper's tables, plots and a leaderboard page; then the committed runs of the same strategies
   (`results/paper/`, 60 tasks x 16 conditions), re-scored.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path
from typing import Any

from talkdem.cli.arguments import folder_path, positive_int

__all__ = ["register"]

DEMO_TASKS = 3
DEMO_LEVEL = 2


def register(subparsers: Any) -> None:
    parser = subparsers.add_parser("demo", help="run the main job on its embedded defaults (make demo)")
    parser.add_argument("--tasks", type=positive_int, default=DEMO_TASKS, help="tasks in the stratified sample")
    parser.add_argument(
        "--level",
        type=int,
        choices=[1, 2, 3],
        default=DEMO_LEVEL,
        help="the level of every pattern in the sample (besides the clean control)",
    )
    parser.add_argument("--model", default="default", help="a model name (`talkdem models`) or GGUF file")
    parser.add_argument("--strategies", default="vanilla,care", help="comma-separated strategies")
    parser.add_argument(
        "--out", type=folder_path, default=Path("demo_output"), help="folder for runs, report, leaderboard"
    )
    parser.add_argument("--threads", type=positive_int, default=2)
    parser.add_argument(
        "--continue-on-new-revision",
        action="store_true",
        help="resume live runs of --out started on another code revision (refused otherwise; both are recorded)",
    )
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    from talkdem.leaderboard import write_leaderboard
    from talkdem.llm.interface.registry import DEFAULT_BACKEND, load_model
    from talkdem.paths import data_dir
    from talkdem.planner.saycan import SayCanConfig
    from talkdem.planner.strategies import load_strategy
    from talkdem.report import score_runs, write_report
    from talkdem.runs.oracle import write_oracle_run
    from talkdem.runs.runner import run_episodes
    from talkdem.runs.sampling import select_episodes
    from talkdem.schema import CLEAN, PATTERN_CONFIGS, Condition

    started = time.perf_counter()
    print("== 1. Task selection: mean pairwise MiniLM similarity (lower = more diverse) ==")
    # The table the selection wrote with the dataset (the demo reads it; it never rebuilds the selection).
    saved = (data_dir() / "selection" / "diversity.md").read_text(encoding="utf-8")
    print("\n".join(line for line in saved.splitlines() if line.startswith("|")))

    conditions = (Condition(CLEAN, 0), *(Condition(pattern, args.level) for pattern in PATTERN_CONFIGS))
    episodes = select_episodes(conditions, args.tasks)
    strategies = [s.strip() for s in args.strategies.split(",") if s.strip()]
    model = load_model(DEFAULT_BACKEND, args.model, threads=args.threads)
    name = model.identity.name
    print(
        f"\n== 2. Live: SayCan with {name} (llama.cpp, {args.threads} threads), {', '.join(strategies)} ==\n"
        f"Sample: the first {args.tasks} task(s) of the stratified order (round robin over task types, not chosen "
        f"for success) x {len(conditions)} conditions (clean + every pattern at level {args.level}) = "
        f"{len(episodes)} episodes per strategy. A small live sample: its rates say little; they show the "
        "pipeline end to end."
    )
    run_dirs = []
    live = time.perf_counter()
    for strategy in strategies:
        run_dir = args.out / "runs" / f"{Path(name).name.removesuffix('.gguf')}-{strategy}"
        summary = run_episodes(
            episodes,
            model,
            load_strategy(strategy),
            run_dir,
            SayCanConfig(),
            extra_config={"conditions": [str(c) for c in conditions], "tasks": args.tasks},
            backend_args={"threads": args.threads},
            new_revision_ok=args.continue_on_new_revision,
        )
        print(f"{strategy}: {summary.ran} run ({summary.successes} successful), {summary.skipped} resumed -> {run_dir}")
        run_dirs.append(run_dir)

    print(f"live runs: {time.perf_counter() - live:.0f} s")

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
    _print_committed_runs(strategies)
    print(f"done in {time.perf_counter() - started:.0f} s")
    return 0


COMMITTED = Path("results") / "paper"


def _print_committed_runs(strategies: list[str]) -> None:
    """The paper's runs committed with the repository for the demo's strategies (default model, 60 tasks x 16
    conditions), re-scored now (not re-run): labelled as what they are, with each run's coverage (a partial run
    says INCOMPLETE), so the live sample's rates can be read against rates over 960 episodes."""
    from talkdem.llm.interface.models import DEFAULT_MODEL
    from talkdem.paths import repo_root
    from talkdem.report import score_runs, success_table

    folder = repo_root() / COMMITTED
    found = [folder / f"{DEFAULT_MODEL}-{strategy}" for strategy in strategies]
    run_dirs = [d for d in found if (d / "header.json").is_file()]
    print(f"\n== 4. The committed runs ({COMMITTED}: recorded runs re-scored now, not run by this demo) ==")
    if not run_dirs:
        print("no committed runs in this installation (they ship with the repository, not the wheel)")
        return
    from talkdem.instructions import dataset_hash

    runs = score_runs(run_dirs, bootstrap=0)
    current = dataset_hash()
    for run in runs:
        header = run.header
        # Runs record the dataset they ran on; say so if data/ has been rebuilt since.
        wording = "" if header.dataset_hash == current else " (an earlier build: not the instructions in data/ now)"
        print(
            f"- {run.label}: {run.coverage.describe()}; model revision {header.model.get('revision', '')[:12]}, "
            f"code {header.code_revision[:12]}, dataset {header.dataset_hash[:12]}{wording}"
        )
    print(success_table(runs).to_markdown())
    print(f"full report: {COMMITTED / 'report' / 'report.md'}; leaderboard: {COMMITTED / 'leaderboard' / 'index.html'}")
