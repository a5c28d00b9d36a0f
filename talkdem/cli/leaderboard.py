"""`talkdem leaderboard`: results files in a stable schema and a static HTML ranking of runs."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

__all__ = ["register"]


def register(subparsers: Any) -> None:
    parser = subparsers.add_parser("leaderboard", help="results JSON per run and a static HTML leaderboard page")
    parser.add_argument("run_dirs", nargs="+", type=Path, metavar="RUN_DIR", help="run directories to score")
    parser.add_argument(
        "--out", type=Path, default=Path("talkdem_leaderboard"), help="output folder (default: %(default)s)"
    )
    parser.add_argument("--bootstrap", type=int, default=0, help="bootstrap resamples (not shown on the page)")
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    from talkdem.leaderboard import results_record, write_leaderboard
    from talkdem.report import score_runs

    runs = score_runs(args.run_dirs, bootstrap=args.bootstrap)
    written = write_leaderboard(runs, args.out)
    for run_ in runs:
        main = results_record(run_)["results"]["talkdem"]
        print(
            f"{run_.label}: clean SR {main['clean_sr']}, average SR {main['average_sr']}, "
            f"average retention {main['average_retention']}, hazard cases {main['hazard_cases']}"
        )
    print(f"results: {args.out / 'results'}")
    print(f"page: {written[-1]}")
    return 0
