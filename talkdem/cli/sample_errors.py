"""`talkdem sample-errors`: the paper's error-analysis sample (N failures per run and pattern-level among
tasks solved clean), seeded, to label by hand in `talkdem view --sample`."""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

from talkdem.cli.arguments import file_path, non_negative_int, positive_int

__all__ = ["register"]


def register(subparsers: Any) -> None:
    parser = subparsers.add_parser(
        "sample-errors",
        help="draw N failures per run and pattern-level (solved clean, failed under the pattern) to label by hand",
    )
    parser.add_argument("run_dirs", nargs="+", type=Path, metavar="RUN_DIR", help="run directories to draw from")
    parser.add_argument(
        "--per-condition", type=positive_int, default=3, help="failures per run and pattern-level (default: 3)"
    )
    parser.add_argument("--seed", type=non_negative_int, default=0, help="random seed (default: 0)")
    parser.add_argument(
        "--out", type=file_path, default=Path("error_sample.json"), help="sample file to write (default: %(default)s)"
    )
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    from talkdem.viewer import load_runs, sample_errors

    runs = load_runs(args.run_dirs)
    sample = sample_errors(runs, args.per_condition, seed=args.seed)
    if args.out.parent != Path(""):
        args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(sample.to_json(), indent=1, ensure_ascii=False) + "\n", encoding="utf-8")
    for run in runs:
        drawn = sum(f.run == run.label for f in sample.failures)
        print(f"{run.label}: {drawn} failures drawn")
    for label, condition, available in sample.short:
        print(f"  {label}, {condition}: only {available} failure(s) solved clean (wanted {args.per_condition})")
    print(f"sample: {args.out} ({len(sample.failures)} failures, seed {args.seed})")
    return 0
