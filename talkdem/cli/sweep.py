"""`talkdem sweep SPEC`: a grid of models x strategies x conditions x tasks, as resumable `talkdem run`
directories, in local processes (`--workers`, `--threads`) or on a Ray cluster (`--ray auto|ADDRESS`)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

from talkdem.cli.arguments import folder_path, positive_int

__all__ = ["register"]


def register(subparsers: Any) -> None:
    parser = subparsers.add_parser(
        "sweep", help="run a YAML grid of models x strategies x conditions x tasks, locally or on Ray"
    )
    parser.add_argument("spec", type=Path, metavar="SPEC", help="the sweep's YAML file (docs/serving.md, 'Sweeps')")
    parser.add_argument("--out", type=folder_path, help="the output root (default: the spec's `out`)")
    parser.add_argument(
        "--only",
        metavar="RUN[,RUN...]",
        help="run (or describe) only these runs of the spec, by folder name (as --dry-run lists them); the "
        "others are left as they are",
    )
    parser.add_argument("--dry-run", action="store_true", help="print the runs and their commands; run nothing")
    parser.add_argument(
        "--workers",
        type=positive_int,
        metavar="N",
        help="jobs at once: local processes (default 1), or Ray actors per model (default: as many as the "
        "cluster holds)",
    )
    parser.add_argument(
        "--threads",
        type=positive_int,
        metavar="T",
        help="hf / llamacpp: CPU threads per worker (default: the CPUs shared among the local workers; on Ray 1)",
    )
    parser.add_argument(
        "--shards",
        type=positive_int,
        metavar="N",
        help="shards per run (default: the spec's `shards`, else one per worker); more shards resume finer",
    )
    parser.add_argument(
        "--ray",
        metavar="auto|ADDRESS",
        help="run on a Ray cluster: auto (the running one), HOST:PORT or ray://HOST:PORT (the `ray` extra)",
    )
    parser.add_argument(
        "--continue-on-new-revision",
        action="store_true",
        help="resume runs started on another code revision (as `talkdem run`'s flag)",
    )
    parser.add_argument("--no-progress", action="store_true", help="no progress lines on stderr")
    parser.set_defaults(handler=sweep)


def sweep(args: argparse.Namespace) -> int:
    from talkdem.sweeps import describe, load_sweep, run_sweep, select_runs

    spec = load_sweep(args.spec, args.out)
    if args.only is not None:
        spec = select_runs(spec, [name.strip() for name in args.only.split(",") if name.strip()])
    if args.dry_run:
        print(describe(spec, workers=args.workers, threads=args.threads, shards=args.shards, ray=args.ray is not None))
        return 0
    result = run_sweep(
        spec,
        workers=args.workers,
        threads=args.threads,
        shards=args.shards,
        ray=args.ray,
        continue_on_new_revision=args.continue_on_new_revision,
        progress=not args.no_progress,
    )
    for model, (loads, jobs) in result.model_loads.items():
        print(f"sweep: {model}: loaded {loads} time(s) by its Ray actors for {jobs} job(s)", file=sys.stderr)
    for run_dir in result.complete:
        print(f"{run_dir}: complete")
    if result.failures:
        for failure in result.failures:
            print(f"talkdem sweep: failed: {failure}", file=sys.stderr)
        left = len(spec.runs) - len(result.complete)
        print(
            f"talkdem sweep: {left} of {len(spec.runs)} runs not complete; run the sweep again to resume",
            file=sys.stderr,
        )
        return 1
    return 0
