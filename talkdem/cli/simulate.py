"""`talkdem simulate`: execute a plan for one task in the symbolic simulator (see talkdem.sim)."""

from __future__ import annotations

import argparse
from typing import Any

__all__ = ["register"]


def register(subparsers: Any) -> None:
    parser = subparsers.add_parser("simulate", help="execute a plan (JSON list of skills) for one task")
    parser.add_argument("--task", required=True, help="task id (ALFRED trial id)")
    parser.add_argument("--plan-file", required=True, help="JSON list of skill strings; '-' reads standard input")
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    raise NotImplementedError("the simulator lands with the simulator issue")
