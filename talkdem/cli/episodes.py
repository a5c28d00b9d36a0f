"""`talkdem episodes` and `talkdem skills`: what an agent author needs to run exactly the benchmark's selection."""

from __future__ import annotations

import argparse
import json
import sys
from typing import Any

from talkdem.cli.arguments import positive_int

__all__ = ["register"]


def register(subparsers: Any) -> None:
    episodes = subparsers.add_parser(
        "episodes", help="list the episodes of a --limit/--conditions selection (the ones `talkdem run` plans), JSONL"
    )
    episodes.add_argument(
        "--conditions",
        help="comma-separated: clean (no levels), PATTERN (all levels) or PATTERN:LEVEL (1-3); default: all 16",
    )
    episodes.add_argument(
        "--limit", type=positive_int, help="number of tasks (stratified over task types; default: all 300)"
    )
    episodes.set_defaults(handler=run_episodes)
    skills = subparsers.add_parser("skills", help="list the 214 skills of the action vocabulary, one a line")
    skills.add_argument("--format", choices=["text", "jsonl"], default="text")
    skills.set_defaults(handler=run_skills)


def run_episodes(args: argparse.Namespace) -> int:
    from talkdem.runs.sampling import select_episodes
    from talkdem.schema import parse_conditions

    for instruction in select_episodes(parse_conditions(args.conditions), args.limit):
        row = {
            "episode_id": instruction.id,
            "task_id": instruction.task_id,
            "task_type": instruction.task_type,
            "pattern": instruction.condition.pattern,
            "level": instruction.condition.level,
            "instruction": instruction.text,
        }
        sys.stdout.write(json.dumps(row, ensure_ascii=False) + "\n")
    return 0


def run_skills(args: argparse.Namespace) -> int:
    from talkdem.skills import vocabulary

    for skill in vocabulary():
        if args.format == "jsonl":
            row = {"skill": skill.text, "verb": skill.verb.value, "object_type": skill.object_type}
            sys.stdout.write(json.dumps(row) + "\n")
        else:
            sys.stdout.write(skill.text + "\n")
    return 0
