"""`talkdem parity`: replay the stored perturbed plans on a backend and report agreement (see talkdem.sim.parity)."""

from __future__ import annotations

import argparse
import sys
from typing import Any

__all__ = ["register"]


def _positive(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got '{text}'") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {value}")
    return value


def register(subparsers: Any) -> None:
    parser = subparsers.add_parser(
        "parity",
        help="replay the perturbed reference plans and report agreement with the stored simulator verdicts",
    )
    parser.add_argument("--backend", choices=("symbolic", "ai2thor"), default="symbolic", help="default: symbolic")
    parser.add_argument("--limit", type=_positive, help="replay only the first N cases")
    parser.add_argument("--ai2thor-build", help="path to an AI2-THOR Unity build (--backend ai2thor)")
    parser.add_argument(
        "--write", action="store_true", help="rebuild data/parity/cases.jsonl from the symbolic backend"
    )
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    from talkdem.sim import AI2ThorExecutor, AI2ThorUnavailableError, SymbolicExecutor
    from talkdem.sim.parity import build_cases, format_report, load_cases, parity_file, replay, write_cases
    from talkdem.tasks import TaskSet, load_tasks

    tasks = load_tasks(TaskSet.BENCHMARK)
    path = parity_file()
    if args.write:
        if args.backend != "symbolic" or args.limit is not None:
            print("talkdem parity: error: --write rebuilds every case from the symbolic backend", file=sys.stderr)
            return 2
        cases = build_cases(tasks, SymbolicExecutor())
        write_cases(cases, path)
        print(f"wrote {len(cases)} cases for {len(tasks)} tasks to data/parity/{path.name}")
        return 0
    executor = SymbolicExecutor() if args.backend == "symbolic" else AI2ThorExecutor(args.ai2thor_build)
    try:
        report = replay(load_cases(path), {t.task_id: t for t in tasks}, executor, args.limit)
    except AI2ThorUnavailableError as exc:
        print(f"talkdem parity: error: {exc}", file=sys.stderr)
        return 2
    print(format_report(report))
    # Against its own stored verdicts the symbolic backend must agree everywhere: a difference is a regression.
    return 0 if args.backend != "symbolic" or not report.disagreements else 1
