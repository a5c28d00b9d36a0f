"""`talkdem view`: a static viewer of run directories (every episode, filters, search, the error sample to
label in the browser); works from file:// and as a static Space."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from talkdem.cli.arguments import folder_path, positive_int

__all__ = ["register"]


def register(subparsers: Any) -> None:
    parser = subparsers.add_parser(
        "view", help="a static page to browse every episode of run directories and label failures"
    )
    parser.add_argument("run_dirs", nargs="+", type=Path, metavar="RUN_DIR", help="run directories to show")
    parser.add_argument(
        "--out", type=folder_path, default=Path("talkdem_viewer"), help="folder to write (default: %(default)s)"
    )
    parser.add_argument(
        "--sample",
        type=Path,
        metavar="FILE",
        help="an error sample from `talkdem sample-errors` over the same runs: its failures are offered for labelling",
    )
    parser.add_argument(
        "--chunk-size", type=positive_int, default=200, help="episodes per detail file loaded on demand (default: 200)"
    )
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    from talkdem.viewer import load_runs, read_sample, write_viewer

    sample = read_sample(args.sample) if args.sample is not None else None
    runs = load_runs(args.run_dirs)
    files = write_viewer(runs, args.out, sample=sample, chunk_size=args.chunk_size)
    sampled = f", {files.sampled} in the error sample" if sample is not None else ""
    print(f"{files.episodes} episodes of {len(runs)} run(s){sampled}; {len(files.chunks)} detail files")
    print(f"page: {files.page}")
    return 0
