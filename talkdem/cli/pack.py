"""`talkdem pack`: store run directories' episodes gzipped (`episodes.jsonl.gz`), or back with `--unpack`."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

__all__ = ["register"]


def register(subparsers: Any) -> None:
    parser = subparsers.add_parser(
        "pack", help="gzip run directories' episodes (every command reads packed runs; a resume unpacks)"
    )
    parser.add_argument("run_dirs", type=Path, nargs="+", metavar="RUN_DIR", help="run directories")
    parser.add_argument("--unpack", action="store_true", help="turn packed runs back into episodes.jsonl")
    parser.add_argument(
        "--partial", action="store_true", help="pack runs that are not complete too (default: complete runs only)"
    )
    parser.set_defaults(handler=pack)


def _size(count: int) -> str:
    return f"{count / 1e6:.1f} MB" if count >= 100_000 else f"{count / 1e3:.1f} KB"


def pack(args: argparse.Namespace) -> int:
    from talkdem.runs.pack import pack_run, unpack_run
    from talkdem.runs.store import read_header

    for run_dir in args.run_dirs:  # every name checked before anything is packed
        if not run_dir.is_dir():
            raise ValueError(f"{run_dir}: not a run directory (no such folder)")
        read_header(run_dir)
    left = 0
    for run_dir in args.run_dirs:
        # Named as typed: the lines may be pasted into a log or a pull request.
        if args.unpack:
            result = unpack_run(run_dir)
            done = "unpacked" if result.changed else "not packed"
        else:
            result = pack_run(run_dir, partial=args.partial)
            done = "packed" if result.changed else "already packed"
        if result.note:
            left += 1
            print(f"{run_dir}: not packed, {result.note}", file=sys.stderr)
        elif result.changed:
            print(f"{run_dir}: {done}, {_size(result.size_before)} -> {_size(result.size_after)}")
        else:
            print(f"{run_dir}: {done} ({_size(result.size_after)})")
    return 1 if left else 0
