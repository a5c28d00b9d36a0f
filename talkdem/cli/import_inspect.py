"""`talkdem import-inspect LOG --out RUN_DIR [--epoch N]`: an inspect_ai log of the TALK-Dem task as a run
directory. A log of several epochs (`inspect eval --epochs K`) is imported one epoch at a time."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from talkdem.cli.arguments import positive_int

__all__ = ["register"]


def register(subparsers: Any) -> None:
    parser = subparsers.add_parser(
        "import-inspect", help="turn an inspect_ai log of the TALK-Dem task into a run directory (report reads it)"
    )
    parser.add_argument("log", type=Path, help="the .eval (or .json) log `inspect eval` wrote")
    parser.add_argument("--out", type=Path, required=True, help="run directory to write (resumes the same log)")
    parser.add_argument(
        "--epoch",
        type=positive_int,
        help="which epoch of a log of several (inspect eval --epochs K) to import; each epoch goes into its own "
        "--out, since a run holds one episode per id (a log of several epochs is refused without it)",
    )
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    from talkdem.evals.inspect_import import import_inspect_log

    summary = import_inspect_log(args.log, args.out, epoch=args.epoch)
    epoch = f" of epoch {summary.epoch}" if summary.epoch is not None else ""
    left_out = f", {summary.errored} errored samples left out" if summary.errored else ""
    print(
        f"{summary.run_dir}: {summary.imported} episodes{epoch} imported ({summary.successes} successful)"
        f"{left_out}; the run is {summary.status} ({summary.in_run} of {summary.planned} planned episodes)"
    )
    return 0
