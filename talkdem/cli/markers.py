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
    return 0 if all(d["holds"] for d in report["directions"]) else 1
