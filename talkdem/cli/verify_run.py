"""`talkdem verify-run RUN_DIR`: re-execute a run's plans and list the records that disagree (exit 1 if any)."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

__all__ = ["register"]


def register(subparsers: Any) -> None:
    parser = subparsers.add_parser(
        "verify-run", help="re-execute a run directory's plans; list the episodes whose stored outcome disagrees"
    )
    parser.add_argument("run_dirs", nargs="+", type=Path, metavar="RUN_DIR")
    parser.add_argument("--json", action="store_true", help="one JSON object per disagreeing episode")
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    from talkdem.runs.verify import verify_run

    disagreeing = 0
    for run_dir in args.run_dirs:
        checked, found = verify_run(run_dir)
        disagreeing += len(found)
        for item in found:
            if args.json:
                row = {"run": run_dir.name, "episode_id": item.episode_id, "fields": list(item.fields)}
                row.update(stored=item.stored, replayed=item.replayed)
                sys.stdout.write(json.dumps(row, ensure_ascii=False) + "\n")
            else:
                print(f"{run_dir}: {item.episode_id}: {', '.join(item.fields)} differ")
        print(f"{run_dir}: {checked} episodes re-executed, {len(found)} disagree", file=sys.stderr)
    return 1 if disagreeing else 0
