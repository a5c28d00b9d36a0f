"""The `talkdem` command: one entry point, one module per subcommand.

Each subcommand module exposes `register(subparsers)`; heavy libraries are imported inside the command
functions, so `talkdem --help` never loads torch, transformers or datasets.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from talkdem import __version__
from talkdem.cli import (
    build,
    demo,
    leaderboard,
    markers,
    models,
    push,
    report,
    run,
    score,
    select,
    simulate,
    tasks,
    verify,
)

__all__ = ["build_parser", "main"]

_COMMANDS = (tasks, select, simulate, demo, build, verify, markers, push, run, score, report, leaderboard, models)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="talkdem",
        description="TALK-Dem: robot task planning under dementia-associated communication.",
    )
    parser.add_argument("--version", action="version", version=f"talkdem {__version__}")
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for command in _COMMANDS:
        command.register(subparsers)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        code: int = args.handler(args)
    except BrokenPipeError:  # `talkdem tasks | head` should end quietly
        return 0
    except (FileNotFoundError, ValueError, KeyError) as exc:
        print(f"talkdem {args.command}: error: {exc}", file=sys.stderr)
        return 2
    return code
