"""`talkdem split`: turn a run under way into shard directories (seeded with its finished episodes), so the
rest can run on several machines (`talkdem run --shard I/N`) and be joined back with `talkdem merge`."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from talkdem.cli.arguments import folder_path, positive_int

__all__ = ["register"]


def register(subparsers: Any) -> None:
    parser = subparsers.add_parser(
        "split", help="split a run under way into shard directories seeded with its finished episodes"
    )
    parser.add_argument("run_dir", type=Path, metavar="RUN_DIR", help="a `talkdem run` directory")
    parser.add_argument("--shards", type=positive_int, required=True, metavar="N", help="number of shards (>= 2)")
    parser.add_argument("--out", type=folder_path, required=True, help="new or empty folder for OUT/shard-I-of-N")
    parser.add_argument(
        "--conditions", help="a larger selection's conditions (default: the run's own; as in `talkdem run`)"
    )
    parser.add_argument("--limit", type=positive_int, help="a larger selection's task count (default: the run's)")
    parser.set_defaults(handler=split)


def split(args: argparse.Namespace) -> int:
    from talkdem.runs.shards import split_run

    shards = split_run(args.run_dir, args.shards, args.out, args.conditions, args.limit)
    for shard in shards:
        print(
            f"{shard.run_dir}: shard {shard.shard}, {shard.seeded} of {shard.planned} episodes already done; "
            f"resume with `talkdem run ... --shard {shard.shard} --out {shard.run_dir}`"
        )
    print(f"then: talkdem merge MERGED_DIR {' '.join(str(s.run_dir) for s in shards)}")
    return 0
