"""`talkdem leaderboard`: results files (Hub template shape) and a static Space folder ranking the runs."""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

from talkdem.cli.arguments import bootstrap_count, folder_path, page_link

__all__ = ["register"]


def register(subparsers: Any) -> None:
    parser = subparsers.add_parser(
        "leaderboard", help="results JSON per run and a static Space folder (README.md, index.html, results/)"
    )
    parser.add_argument("run_dirs", nargs="*", type=Path, metavar="RUN_DIR", help="run directories to score")
    parser.add_argument(
        "--out",
        type=folder_path,
        default=Path("talkdem_leaderboard"),
        help="Space folder to write (default: %(default)s)",
    )
    parser.add_argument("--from-results", type=Path, metavar="DIR", help="also show the results files under DIR")
    parser.add_argument(
        "--bootstrap",
        type=bootstrap_count,
        default=1000,
        help="bootstrap resamples for the 95%% intervals: 0 (no intervals) or at least 40 (default: %(default)s)",
    )
    parser.add_argument(
        "--viewer", type=page_link, metavar="HREF", help="link the page to the episode viewer (`talkdem view`)"
    )
    parser.set_defaults(handler=run)


def _percent(value: float | None) -> str:
    """A rate as the page shows it (percent, one decimal; `–` where undefined), not the stored fraction."""
    return "–" if value is None else f"{100 * value:.1f}%"


def run(args: argparse.Namespace) -> int:
    from talkdem.leaderboard import (
        RANK_KEY,
        rank_records,
        read_results,
        results_record,
        write_leaderboard,
        write_space,
    )
    from talkdem.report import score_runs

    if not args.run_dirs and args.from_results is None:
        raise ValueError("give run directories, --from-results DIR, or both")
    runs = score_runs(args.run_dirs, bootstrap=args.bootstrap) if args.run_dirs else []
    if args.from_results is not None:
        if not args.from_results.is_dir():
            raise FileNotFoundError(f"{args.from_results}: no such results folder")
        fresh = [results_record(r) for r in runs]
        ids = {r["run_id"] for r in fresh}
        found = read_results(args.from_results)
        if not found:
            # Most likely a wrong folder: a page built from nothing and exit 0 would look like a success.
            raise FileNotFoundError(f"{args.from_results}: no results files (*.json) under this folder")
        records = [r for r in found if r["run_id"] not in ids] + fresh
        written = write_space(records, args.out, viewer=args.viewer)
    else:
        written = write_leaderboard(runs, args.out, viewer=args.viewer)
    # What the page shows: the runs given plus results already in the folder.
    standings = rank_records(json.loads((args.out / "leaderboard.json").read_text(encoding="utf-8")))
    print(f"rank key: {RANK_KEY}")
    for i, group in enumerate(standings.groups, start=1):
        print(
            f"group {i} ({group.coverage['tasks']}/{group.coverage['of_tasks']} tasks, "
            f"{group.coverage['conditions']} conditions):"
        )
        for rank, record in group.ranked:
            main = record["results"]["talkdem"]
            print(
                f"  {rank}. {record['config']['run_name']}: average SR {_percent(main['average_sr'])}, "
                f"average retention {_percent(main['average_retention'])}, clean SR {_percent(main['clean_sr'])}"
            )
    for record in standings.reference:
        print(f"  reference plans (not ranked): {record['config']['run_name']}")
    print(f"results: {args.out / 'results'}")
    print(f"page: {written[-1]}")
    return 0
