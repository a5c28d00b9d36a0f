"""`talkdem report`: score run directories and print/write the paper's tables and figures."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

from talkdem.cli.arguments import bootstrap_count, folder_path, page_link

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
    parser.add_argument(
        "--no-paper",
        action="store_true",
        help="leave out the paper's own figures (other models), which are otherwise set beside ours, marked (paper)",
    )
    parser.add_argument(
        "--labels",
        type=Path,
        metavar="FILE",
        help="error types labelled by people (exported from `talkdem view`): their error-by-pattern table and "
        "the agreement with the automatic classifier (Cohen's kappa, confusion matrix)",
    )
    parser.add_argument(
        "--viewer", type=page_link, metavar="HREF", help="link the report to the episode viewer (`talkdem view`)"
    )
    parser.set_defaults(handler=run)


def _strategy_label(text: str) -> str:
    from talkdem.report.runs import STRATEGY_LABELS

    for name, label in STRATEGY_LABELS.items():
        if text.lower() in (name, label.lower()):
            return label
    raise argparse.ArgumentTypeError(f"unknown strategy '{text}' (known: {', '.join(STRATEGY_LABELS.values())})")


def run(args: argparse.Namespace) -> int:
    from talkdem.report import score_runs, write_report

    if args.labels is not None and not args.labels.is_file():  # before minutes of scoring, not after
        raise FileNotFoundError(f"{args.labels}: no such labels file (export one from `talkdem view`)")
    runs = score_runs(args.run_dirs, bootstrap=args.bootstrap)
    for scored in runs:
        orphans = scored.scores.without_clean_twin
        if orphans:  # the report shows retention as '–' for this run: say why, once
            print(
                f"talkdem report: {scored.run_dir}: retention left out: {len(orphans)} pattern episode(s) have no "
                f"clean episode of their task in the run (e.g. {orphans[0]}); include clean in the run's "
                "conditions to measure it",
                file=sys.stderr,
            )
    extra = []
    if args.labels is not None:
        from talkdem.viewer.labels import label_tables, read_labels

        extra = label_tables(read_labels(args.labels, runs), args.labels.name)
    files = write_report(
        runs,
        args.out,
        reference_strategy=args.reference_strategy,
        plots=not args.no_plots,
        paper=not args.no_paper,
        extra_tables=extra,
        viewer=args.viewer,
    )
    for table in files.tables:
        print(table.to_markdown())
    print(f"report: {files.markdown}")
    print(f"page: {files.html}")
    print(f"tables: {args.out / 'tables'} ({len(files.table_files)} files)")
    print(f"scores: {', '.join(str(p) for p in files.score_files)}")
    if files.plots:
        print(f"plots: {', '.join(str(p) for p in files.plots)}")
    return 0
