"""`talkdem demo`: the main job on its embedded defaults (what `make demo` runs)."""

from __future__ import annotations

import argparse
from typing import Any

__all__ = ["register"]


def register(subparsers: Any) -> None:
    parser = subparsers.add_parser("demo", help="run the main job on its embedded defaults")
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    from talkdem.cli import select

    print("== TALK-Dem task selection (greedy max-min over all-MiniLM-L6-v2 embeddings) ==")
    return select.run(argparse.Namespace(alfred_dir=None, floorplans_dir=None, write=False, saved=False))
