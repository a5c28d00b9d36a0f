"""`talkdem import-inspect LOG --out RUN_DIR`: an inspect_ai log of the TALK-Dem task as a run directory."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

__all__ = ["register"]


def register(subparsers: Any) -> None:
    parser = subparsers.add_parser(
        "import-inspect", help="turn an inspect_ai log of the TALK-Dem task into a run directory (report reads it)"
    )
    parser.add_argument("log", type=Path, help="the .eval (or .json) log `inspect eval` wrote")
    parser.add_argument("--out", type=Path, required=True, help="run directory to write (resumes the same log)")
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    from talkdem.evals.inspect_import import import_inspect_log

    summary = import_inspect_log(args.log, args.out)
    left_out = f", {summary.errored} errored samples left out" if summary.errored else ""
    print(f"{summary.run_dir}: {summary.imported} episodes imported ({summary.successes} successful){left_out}")
    return 0
