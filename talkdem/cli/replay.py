"""`talkdem replay`: rebuild a dataset folder from the choices its rows recorded, without the ranking model.

Two uses: check that a (ranked) dataset is what the current builder writes, in minutes instead of the hours a
ranking model takes on a CPU; and choose again among the recorded candidates with another `--rank-margin`.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

from talkdem.cli.arguments import folder_path

__all__ = ["register"]


def register(subparsers: Any) -> None:
    parser = subparsers.add_parser(
        "replay",
        help="rebuild a dataset folder from its rows' recorded ranking choices (no model), or with another margin",
    )
    parser.add_argument("source", type=Path, metavar="SOURCE", help="a built dataset folder (e.g. data)")
    parser.add_argument("--out", type=folder_path, required=True, help="folder to write (new, empty or a dataset)")
    parser.add_argument(
        "--rank-margin",
        type=float,
        help="choose again from the recorded scores with this margin (nats per token; a ranked SOURCE only); "
        "default: the margin SOURCE was built with",
    )
    parser.add_argument("--tasks-dir", type=Path, help="folder holding tasks/*.jsonl (default: data/)")
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    from builders.replay import replay

    if args.out.resolve() == args.source.resolve():
        raise ValueError(f"{args.out}: --out is SOURCE; replay reads SOURCE while it writes, give another folder")
    stats = replay(args.source, args.out, tasks_folder=args.tasks_dir, margin=args.rank_margin)
    print(json.dumps({"folder": str(args.out), **stats}, indent=2))
    return 0
