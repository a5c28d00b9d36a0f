"""`talkdem push`: publish the dataset folder, or a leaderboard folder as a Space (and its results as a
dataset), to the Hugging Face Hub."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

from talkdem.cli.arguments import hub_repo_id

__all__ = ["register"]


def register(subparsers: Any) -> None:
    parser = subparsers.add_parser(
        "push", help="upload the dataset folder, or a leaderboard folder as a static Space, to the Hub"
    )
    parser.add_argument(
        "--repo",
        required=True,
        type=hub_repo_id,
        help="ORG/NAME of the dataset repository (of the Space with --leaderboard)",
    )
    parser.add_argument("--data", type=Path, help="dataset folder (default: data/)")
    parser.add_argument(
        "--leaderboard", type=Path, metavar="DIR", help="publish DIR (`talkdem leaderboard --out DIR`) as a Space"
    )
    parser.add_argument(
        "--results-repo", type=hub_repo_id, metavar="ORG/NAME", help="with --leaderboard: also DIR/results as a dataset"
    )
    parser.add_argument("--private", action="store_true", help="create the repository as private")
    parser.add_argument("--message", default="Upload TALK-Dem", help="commit message")
    parser.add_argument("--dry-run", action="store_true", help="list the files that would be uploaded")
    parser.set_defaults(handler=run)


def _push_leaderboard(args: argparse.Namespace) -> int:
    from talkdem.leaderboard import (
        not_uploaded,
        publish_results,
        publish_space,
        results_upload_plan,
        space_upload_plan,
    )

    folder: Path = args.leaderboard
    # What is left out is said before anything is sent, dry run or not: a file a user expected on the Hub
    # (or a stray one in the folder) must not go unnoticed.
    for path, why in not_uploaded(folder) if (folder / "README.md").is_file() else []:
        print(f"skipped {folder / path}: {why}", file=sys.stderr)
    if args.dry_run:
        for path in space_upload_plan(folder):
            print(f"space {args.repo}: {path}")
        if args.results_repo:
            for path in results_upload_plan(folder):
                print(f"dataset {args.results_repo}: {path}")
        return 0
    url = publish_space(folder, args.repo, private=args.private, message=args.message)
    print(f"uploaded {folder} to the Space {url}", file=sys.stderr)
    if args.results_repo:
        url = publish_results(folder, args.results_repo, private=args.private, message=args.message)
        print(f"uploaded {folder / 'results'} to the dataset {url}", file=sys.stderr)
    return 0


def run(args: argparse.Namespace) -> int:
    if args.leaderboard is not None:
        if args.data is not None:
            raise ValueError("--data and --leaderboard publish different folders: give one")
        return _push_leaderboard(args)
    if args.results_repo:
        raise ValueError("--results-repo needs --leaderboard DIR")
    from builders.push import push, upload_plan
    from talkdem.paths import data_dir

    folder = args.data or data_dir()
    if args.dry_run:
        for path in upload_plan(folder):
            print(path)
        return 0
    url = push(folder, args.repo, private=args.private, message=args.message)
    print(f"uploaded {folder} to {url}", file=sys.stderr)
    return 0
