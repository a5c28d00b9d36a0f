"""`talkdem report`: score run directories and print/write the paper's tables and figures."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from talkdem.cli.arguments import bootstrap_count, folder_path

__all__ = ["register"]


def register(subparsers: Any) -> None:
    parser = subparsers.add_parser(
        "report", help="score run directories: paper tables (md/csv/json), plots and one HTML page"
    )
    parser.add_argument("run_dirs", nargs="+", type=Path, metavar="RUN_DIR", help="run directories to score")
    parser.add_argument(
        "--out", type=folder_path, default=Path("talkdem_report"), help="output folder (default: %(default)s)"
    )
    parser.add_argument(
        "--reference-strategy",
        default="CARE",
        type=_strategy_label,
        help="strategy the retention tests compare with (a strategy name or label, e.g. care or CARE)",
    )
    parser.add_argument(
        "--bootstrap",
        type=bootstrap_count,
        default=1000,
        help="bootstrap resamples for the 95%% intervals: 0 (no intervals) or at least 40 (default: %(default)s)",
    )
    parser.add_argument("--no-plots", action="store_true", help="skip the figures")
    parser.set_defaults(handler=run)


def _strategy_label(text: str) -> str:
    from talkdem.report.runs import STRATEGY_LABELS

    for name, label in STRATEGY_LABELS.items():
        if text.lower() in (name, label.lower()):
            return label
    raise argparse.ArgumentTypeError(f"unknown strategy '{text}' (known: {', '.join(STRATEGY_LABELS.values())})")


def run(args: argparse.Namespace) -> int:
    from talkdem.report import score_runs, write_report

    runs = score_runs(args.run_dirs, bootstrap=args.bootstrap)
    files = write_report(runs, args.out, reference_strategy=args.reference_strategy, plots=not args.no_plots)
    for table in files.tables:
        print(table.to_markdown())
    print(f"report: {files.markdown}")
    print(f"page: {files.html}")
    print(f"tables: {args.out / 'tables'} ({len(files.table_files)} files)")
    print(f"scores: {', '.join(str(p) for p in files.score_files)}")
    if files.plots:
        print(f"plots: {', '.join(str(p) for p in files.plots)}")
    return 0
