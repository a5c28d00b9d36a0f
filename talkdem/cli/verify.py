"""`talkdem verify`: run the deterministic checks on one utterance for one task, pattern and level."""

from __future__ import annotations

import argparse
import json
from typing import Any

__all__ = ["register"]


def register(subparsers: Any) -> None:
    parser = subparsers.add_parser(
        "verify", help='check one utterance: prints {"passed": bool, "failed_checks": [...]}'
    )
    parser.add_argument("--task", required=True, help="ALFRED trial id of a benchmark or memory task")
    parser.add_argument("--pattern", required=True, help="a pattern config name (e.g. topic_drift) or clean")
    parser.add_argument("--level", type=int, default=0, help="1-3 for a pattern (ignored for clean)")
    parser.add_argument("--text", required=True, help="the utterance")
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    from builders.verification import verify
    from talkdem.tasks import get_task

    result = verify(get_task(args.task), args.pattern, args.level, args.text)
    print(json.dumps(result))
    return 0
