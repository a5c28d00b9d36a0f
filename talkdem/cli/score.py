"""`talkdem score`: execute plans written by any other system and store them as a run directory."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from talkdem.cli.arguments import folder_path

__all__ = ["register"]


def register(subparsers: Any) -> None:
    parser = subparsers.add_parser(
        "score", help='execute external plans (JSONL: {"episode_id", "plan"}) into a run directory'
    )
    parser.add_argument("plans", type=Path, help="JSONL file, one episode per line")
    parser.add_argument(
        "--out",
        type=folder_path,
        required=True,
        help="run directory to create, or a run of the same --name to add the plans to",
    )
    parser.add_argument("--name", default="external", help="name of the system that wrote the plans")
    parser.add_argument("--model", default="", help="the model the system ran on (recorded in the header)")
    parser.add_argument("--strategy", default="external", help="the system's prompting strategy, if it has one")
    parser.add_argument("--version", default="", help="the system's version (a new version is another run)")
    parser.add_argument(
        "--continue-on-new-revision",
        action="store_true",
        help="resume a run started on another code revision (refused otherwise); the header records both",
    )
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    from talkdem.runs.episode import out_of_vocabulary_steps
    from talkdem.runs.external import record_plan_file
    from talkdem.runs.store import HEADER_FILE, read_episodes

    before = len(read_episodes(args.out)) if (args.out / HEADER_FILE).is_file() else 0
    count = record_plan_file(
        args.plans,
        args.out,
        args.name,
        args.strategy,
        new_revision_ok=args.continue_on_new_revision,
        model=args.model,
        version=args.version,
    )
    kept = f", {before} already in the run" if before else ""
    print(f"{args.out}: {count - before} episodes executed and scored{kept} ({count} in all)")
    steps, episodes = out_of_vocabulary_steps(args.out)
    if steps:
        print(
            f"{args.out}: {steps} steps in {episodes} episodes name no skill (failed: instruction not supported; "
            "`talkdem skills` lists the vocabulary)"
        )
    return 0
