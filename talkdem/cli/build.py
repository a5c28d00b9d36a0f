"""`talkdem build`: generate, verify and write the whole dataset under `data/` (resumable)."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

__all__ = ["register"]


def register(subparsers: Any) -> None:
    parser = subparsers.add_parser(
        "build",
        help="rebuild the dataset (4,800 instructions + 1,600 memory items) as Parquet with its card",
    )
    parser.add_argument("--generator", default="rules", help="generator name (default: rules; see builders/generation)")
    parser.add_argument("--seed", type=int, default=0, help="build seed (default 0): same seed, same bytes")
    parser.add_argument("--out", type=Path, help="dataset folder (default: data/ or $TALKDEM_DATA_DIR)")
    parser.add_argument("--tasks-dir", type=Path, help="folder holding tasks/*.jsonl (default: data/)")
    parser.add_argument("--checkpoint", type=Path, help="JSONL checkpoint (default: .cache/build/...)")
    parser.add_argument("--no-progress", action="store_true", help="hide the progress bar")
    parser.add_argument(
        "--card-copy", type=Path, help="also write the card here (default: dataset_card.md when --out is data/)"
    )
    parser.add_argument("--throttle", type=float, default=0.0, help=argparse.SUPPRESS)  # resume tests
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    from builders.build import build
    from talkdem.paths import data_dir, repo_root

    out = args.out or data_dir()
    card_copy = args.card_copy
    if card_copy is None and Path(out).resolve() == (repo_root() / "data").resolve():
        card_copy = repo_root() / "dataset_card.md"
    result = build(
        out,
        generator=args.generator,
        seed=args.seed,
        checkpoint=args.checkpoint,
        tasks_folder=args.tasks_dir,
        progress=not args.no_progress,
        throttle=args.throttle,
        card_copy=card_copy,
    )
    if result.resumed_units:
        print(f"resumed {result.resumed_units} finished tasks from the checkpoint", file=sys.stderr)
    print(json.dumps({"folder": str(result.folder), **result.stats}, indent=2))
    return 0
