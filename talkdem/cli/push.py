"""`talkdem push`: publish the dataset folder to the Hugging Face Hub."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

from talkdem.cli.arguments import hub_repo_id

__all__ = ["register"]


def register(subparsers: Any) -> None:
    parser = subparsers.add_parser("push", help="upload the dataset folder (card + Parquet) to a Hub dataset repo")
    parser.add_argument("--repo", required=True, type=hub_repo_id, help="ORG/NAME of the dataset repository")
    parser.add_argument("--data", type=Path, help="dataset folder (default: data/)")
    parser.add_argument("--private", action="store_true", help="create the repository as private")
    parser.add_argument("--message", default="Upload TALK-Dem", help="commit message")
    parser.add_argument("--dry-run", action="store_true", help="list the files that would be uploaded")
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
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
