"""`talkdem simulate`: execute a plan for one task in the symbolic simulator (see talkdem.sim)."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

from talkdem.plans import Plan, check_plan
from talkdem.serialization import parse_json

__all__ = ["register"]


def register(subparsers: Any) -> None:
    parser = subparsers.add_parser("simulate", help="execute a plan (JSON list of skills) for one task")
    parser.add_argument("--task", required=True, help="task id (ALFRED trial id)")
    parser.add_argument("--plan-file", required=True, help="JSON list of skill strings; '-' reads standard input")
    parser.set_defaults(handler=run)


def _read_plan(source: str) -> Plan:
    try:
        text = sys.stdin.read() if source == "-" else Path(source).read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        reason = exc.strerror if isinstance(exc, OSError) else "not UTF-8 text"
        raise ValueError(f"cannot read plan file '{source}': {reason}") from None
    where = "standard input" if source == "-" else source
    try:
        value = parse_json(text, where)
    except ValueError as exc:
        raise ValueError(f"{exc}; expected a JSON list of skill strings") from None
    return check_plan(value, where)


def run(args: argparse.Namespace) -> int:
    from talkdem.sim import run_plan
    from talkdem.tasks import get_task

    task = get_task(args.task)
    plan = _read_plan(args.plan_file)
    print(json.dumps(run_plan(task, plan).summary(), ensure_ascii=False))
    return 0
