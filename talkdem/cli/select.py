"""`talkdem select`: recompute the diversity-based task selection and print the diversity table."""

from __future__ import annotations

import argparse
import sys
from typing import Any

__all__ = ["register"]


def register(subparsers: Any) -> None:
    parser = subparsers.add_parser(
        "select",
        help="recompute the 300 + 100 task selection (MiniLM, greedy max-min) and print the diversity table",
    )
    parser.add_argument("--alfred-dir", help="ALFRED json_2.1.0 folder (default: $TALKDEM_ALFRED_DIR or the seed pool)")
    parser.add_argument("--floorplans-dir", help="folder of FloorPlan<N>-objects.json / -openable.json")
    parser.add_argument(
        "--write",
        action="store_true",
        help="write data/tasks/*.jsonl, data/selection/ and the planner's worked examples (data/prompts/)",
    )
    parser.add_argument("--saved", action="store_true", help="print the saved table without recomputing")
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    from builders.selection import format_diversity_table, load_diversity

    if args.saved:
        if args.write:
            raise ValueError("--saved prints the saved table, --write recomputes the selection and writes it: give one")
        print(format_diversity_table(load_diversity()))
        return 0
    from builders.selection import select_tasks, write_selection
    from talkdem.paths import alfred_dir, floorplans_dir
    from talkdem.seeds import load_seed_pool
    from talkdem.tasks import TaskSet, load_tasks

    root, floorplans = alfred_dir(args.alfred_dir), floorplans_dir(args.floorplans_dir)
    print(f"reading seeds from {root}", file=sys.stderr)
    seeds = load_seed_pool(root, floorplans)
    selection = select_tasks(seeds)
    print(format_diversity_table(selection.diversity))
    print(
        f"\n{len(seeds)} seed files, {len({s.task_id for s in seeds})} distinct trials; "
        f"selected {len(selection.benchmark)} benchmark + {len(selection.memory)} memory tasks; "
        f"{len(selection.shared_with_benchmark)} trials left out of the memory candidates for sharing an ALFRED "
        "task or a seed text with a benchmark task"
    )
    if args.write:
        from builders.planner_examples import write_examples

        for path in write_selection(selection):
            print(f"wrote {path}")
        # The worked examples come from trials in neither task set, so they follow the selection.
        print(f"wrote {write_examples(seeds)}")
        return 0
    try:
        saved = {s.value: [t.task_id for t in load_tasks(s)] for s in TaskSet}
    except FileNotFoundError:
        print("no saved selection to compare with (use --write)")
        return 0
    fresh = {"benchmark": [t.task_id for t in selection.benchmark], "memory": [t.task_id for t in selection.memory]}
    same = saved == fresh
    print("identical to the saved selection in data/tasks/" if same else "DIFFERS from the saved selection")
    return 0 if same else 1
