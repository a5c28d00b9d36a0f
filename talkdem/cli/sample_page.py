"""`talkdem sample-page DATA_DIR --out FILE.html`: one self-contained HTML page to read a sample of the dataset."""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

__all__ = ["register"]

DEFAULT_PER_TYPE = 5


def _tasks_per_type(value: str) -> int | None:
    if value == "all":
        return None
    try:
        number = int(value)
    except ValueError:
        number = 0
    if number < 1:
        raise argparse.ArgumentTypeError(f"expected a positive number of tasks per task type or 'all', got {value!r}")
    return number


def register(subparsers: Any) -> None:
    parser = subparsers.add_parser(
        "sample-page",
        help="write one self-contained HTML page: per task the seed, the clean control and the 15 variants side "
        "by side, the inserted words highlighted, with filters",
    )
    parser.add_argument("data", type=Path, metavar="DATA_DIR", help="dataset folder (e.g. data/)")
    parser.add_argument("--out", type=Path, required=True, help="the HTML file to write (e.g. data/sample.html)")
    parser.add_argument(
        "--tasks",
        type=_tasks_per_type,
        default=DEFAULT_PER_TYPE,
        metavar="N|all",
        help=f"tasks per task type, evenly spaced in task-id order (default {DEFAULT_PER_TYPE}), or 'all'",
    )
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    from talkdem.dataset_page import load_page_tasks, sample_tasks, write_sample_page

    folder: Path = args.data
    if not (folder / "README.md").is_file():
        raise ValueError(f"{folder}: not a dataset folder (no README.md card declaring its configs)")
    tasks = load_page_tasks(folder)
    chosen = sample_tasks(tasks, args.tasks)
    out = write_sample_page(chosen, len(tasks), args.out, args.tasks)
    print(f"wrote {out} ({len(chosen)} of {len(tasks)} tasks)")
    # The card links the page only when it is there: writing it beside the card refreshes the card.
    stats_file = folder / "build_stats.json"
    if out.resolve() == (folder / "sample.html").resolve() and stats_file.is_file():
        from builders.card import write_card

        for path in write_card(folder, json.loads(stats_file.read_text())):
            print(f"wrote {path.name}")
    return 0
