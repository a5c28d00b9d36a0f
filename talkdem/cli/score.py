"""`talkdem score`: execute plans written by any other system and store them as a run directory."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

__all__ = ["register"]


def register(subparsers: Any) -> None:
    parser = subparsers.add_parser(
        "score", help='execute external plans (JSONL: {"episode_id", "plan"}) into a run directory'
    )
    parser.add_argument("plans", type=Path, help="JSONL file, one episode per line")
    parser.add_argument("--out", type=Path, required=True, help="run directory to create")
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
    from talkdem.runs.external import score_plan_file

    count = score_plan_file(
        args.plans,
        args.out,
        args.name,
        args.strategy,
        new_revision_ok=args.continue_on_new_revision,
        model=args.model,
        version=args.version,
    )
    steps, episodes = out_of_vocabulary_steps(args.out)
    flagged = (
        f"; {steps} steps in {episodes} episodes name no skill (failed: instruction not supported; "
        "`talkdem skills` lists the vocabulary)"
        if steps
        else "; every step names a skill"
    )
    print(f"{args.out}: {count} episodes executed and scored{flagged}")
    return 0
