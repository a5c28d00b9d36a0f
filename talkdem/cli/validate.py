"""`talkdem validate-dataset DIR`: independent markers, fluency and masked variety of a dataset folder."""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

from talkdem.cli.arguments import positive_int

__all__ = ["register"]


def register(subparsers: Any) -> None:
    parser = subparsers.add_parser(
        "validate-dataset",
        help="independent markers (spaCy), fluency (SmolLM2-135M) and masked variety; writes validation.json/.md",
    )
    parser.add_argument("data", type=Path, metavar="DIR", help="dataset folder (e.g. data)")
    parser.add_argument("--out", type=Path, help="where to write validation.json and validation.md (default: DIR)")
    parser.add_argument("--no-fluency", action="store_true", help="skip the fluency scores (no language model)")
    parser.add_argument("--fluency-cache", type=Path, help="score cache file (default: under the talkdem cache)")
    parser.add_argument(
        "--threads", type=positive_int, default=1, help="llama.cpp threads of the fluency model (default 1)"
    )
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    from builders.validation.report import run_validation

    report = run_validation(
        args.data, args.out, fluency=not args.no_fluency, fluency_cache=args.fluency_cache, threads=args.threads
    )
    stats_file = args.data / "build_stats.json"
    if (args.out is None or args.out.resolve() == args.data.resolve()) and stats_file.is_file():
        # the card shows validation.json: refresh it as `talkdem markers` does (here, not in builders.validation,
        # which must not load the card's imports of the generator-side markers)
        from builders.card import write_card

        write_card(args.data, json.loads(stats_file.read_text()))
    for column in ("ours", "independent"):
        summary = report["markers"][column]
        if summary is not None:
            print(
                f"{column}: {summary['cells_within_tolerance']}/{summary['cells']} cells within tolerance, "
                f"{summary['markers_moving_as_paper']}/{summary['markers']} markers move as in the paper"
            )
    print(f"wrote validation.json and validation.md in {args.out or args.data}")
    return 0
