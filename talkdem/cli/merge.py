"""`talkdem merge`: join the shard run directories of one run (`talkdem run --shard I/N`) into one."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

__all__ = ["register"]


def register(subparsers: Any) -> None:
    parser = subparsers.add_parser("merge", help="join shard run directories (`run --shard I/N`) into one run")
    parser.add_argument("out", type=Path, help="the merged run directory (new or empty)")
    parser.add_argument("shards", type=Path, nargs="+", metavar="SHARD_DIR", help="shard run directories")
    parser.add_argument(
        "--allow-incomplete", action="store_true", help="write the merge even when episodes are missing (listed)"
    )
    parser.set_defaults(handler=merge)


def merge(args: argparse.Namespace) -> int:
    from talkdem.runs.shards import merge_runs

    result = merge_runs(args.out, args.shards, allow_incomplete=args.allow_incomplete)
    print(f"{result.out}: {result.episodes} episodes from {len(args.shards)} shard directories")
    if result.missing:
        shown = ", ".join(result.missing[:10]) + (
            f" and {len(result.missing) - 10} more" if len(result.missing) > 10 else ""
        )
        print(f"INCOMPLETE: {len(result.missing)} episodes missing: {shown}", file=sys.stderr)
        return 1
    return 0
