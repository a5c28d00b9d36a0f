"""`talkdem retrieval`: CARE's top-1 retrieval diagnostics on a dataset folder (same pattern, target, type)."""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

__all__ = ["register"]


def register(subparsers: Any) -> None:
    parser = subparsers.add_parser(
        "retrieval",
        help="how often CARE's top-1 memory item shares the query's pattern, target object and task type; "
        "writes selection/retrieval.json and refreshes the card",
    )
    parser.add_argument("--data", type=Path, help="dataset folder (default: data/)")
    parser.add_argument("--no-write", action="store_true", help="print only; do not write the report or the card")
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    from builders.selection.retrieval import RetrievalRow, compute_retrieval, retrieval_table, write_retrieval
    from talkdem.paths import data_dir

    folder = Path(args.data) if args.data else data_dir()
    report = compute_retrieval(folder)
    print(retrieval_table([RetrievalRow(**row) for row in report["rows"]]))
    if not args.no_write:
        print(f"wrote {write_retrieval(folder, report).name} under selection/")
        stats_file = folder / "build_stats.json"
        if stats_file.is_file():
            from builders.card import write_card

            for path in write_card(folder, json.loads(stats_file.read_text())):
                print(f"wrote {path.name}")
    return 0
