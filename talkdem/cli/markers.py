"""`talkdem markers`: dementia-associated linguistic markers of the shipped data (and optional DementiaBank)."""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

__all__ = ["register"]


def register(subparsers: Any) -> None:
    parser = subparsers.add_parser(
        "markers",
        help="compute the paper's linguistic markers per pattern and level (spaCy, MiniLM) and update the card",
    )
    parser.add_argument("--data", type=Path, help="dataset folder (default: data/)")
    parser.add_argument("--no-relevance", action="store_true", help="skip task relevance (no sentence encoder)")
    parser.add_argument("--chat-dir", type=Path, help="DementiaBank CHAT folder with dementia/ and control/ subfolders")
    parser.add_argument("--reference-text", help="reference text for CHAT relevance (e.g. a Cookie Theft description)")
    parser.add_argument("--no-write", action="store_true", help="print only; do not write markers.json or the card")
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    from builders.markers.report import run_markers

    report = run_markers(
        args.data,
        relevance=not args.no_relevance,
        chat_dir=args.chat_dir,
        reference_text=args.reference_text,
        write=not args.no_write,
    )
    print(report["table"])
    if "dementiabank" in report:
        print(json.dumps(report["dementiabank"], indent=2))
    from builders.markers.paper import follows_papers_column

    # A marker fails only where it moves neither as the paper's arrow nor, where that column turns back, as the
    # paper's own column: the paper's data is the reference, and it does not move monotonically everywhere.
    failing = [
        f"{d['marker']} ({d['pattern']})"
        for d in report["directions"]
        if not (d["holds"] or follows_papers_column(d["marker"], d["pattern"], d["values"]))
    ]
    if failing:
        print(f"markers: moving neither as the paper's arrow nor as its column: {', '.join(failing)}")
    return 1 if failing else 0
