"""`talkdem simulate`: execute a plan for one task in the symbolic simulator (see talkdem.sim)."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

__all__ = ["register"]


def register(subparsers: Any) -> None:
    parser = subparsers.add_parser("simulate", help="execute a plan (JSON list of skills) for one task")
    parser.add_argument("--task", required=True, help="task id (ALFRED trial id)")
    parser.add_argument("--plan-file", required=True, help="JSON list of skill strings; '-' reads standard input")
    parser.set_defaults(handler=run)


def _read_plan(source: str) -> list[str]:
    try:
        text = sys.stdin.read() if source == "-" else Path(source).read_text(encoding="utf-8")
    except OSError as exc:
        raise ValueError(f"cannot read plan file '{source}': {exc.strerror}") from exc
    where = "standard input" if source == "-" else source
    try:
        plan = json.loads(text)
    except json.JSONDecodeError as exc:
        raise ValueError(
            f"{where} is not JSON ({exc.msg}, line {exc.lineno}); expected a list of skill strings"
        ) from None
    if not isinstance(plan, list) or not all(isinstance(step, str) for step in plan):
        raise ValueError(f'{where} must be a JSON list of skill strings, e.g. ["find an apple", "done"]')
    return plan


def run(args: argparse.Namespace) -> int:
    from talkdem.sim import run_plan
    from talkdem.tasks import get_task

    task = get_task(args.task)
    plan = _read_plan(args.plan_file)
    print(json.dumps(run_plan(task, plan).summary(), ensure_ascii=False))
    return 0
