"""Rebuild a dataset folder with the current generator, taking its ranking choices from its own rows.

A ranked build takes hours on a CPU (a language model scores every verified candidate), so "the shipped data is
what the builder writes" cannot be checked by ranking again. It is checked by replaying: every task is built
again by the current generator and verifier, and wherever the build chose among verified candidates, the choice
recorded in the row is taken with its recorded score (`RecordedRanker`). The replay writes the same bytes only
if every shipped row is still a verified candidate of its request at the attempt it records, with the same
verification, candidate counts and statistics; that the model would choose the same candidates again is checked
on a sample of tasks by ranking them (tests/dataset/test_replay.py).

An unranked dataset replays as a plain build.
"""

from __future__ import annotations

import json
from collections import defaultdict
from pathlib import Path
from typing import Any

from builders.build import build_unit, check_output_folder, write_dataset
from builders.generation.ranking import RecordedRanker, checked_margin
from talkdem.paths import data_dir
from talkdem.schema import CLEAN, MEMORY_BANK, PATTERN_CONFIGS, TASKS, data_files, features
from talkdem.speech.base import get_generator
from talkdem.tasks import Task, TaskSet, load_tasks

__all__ = ["recorded_rows", "replay"]


def recorded_rows(folder: Path) -> dict[str, list[dict[str, Any]]]:
    """The rows of a dataset folder by unit key (`benchmark:<task>` or `memory:<task>`), as the build wrote them."""
    import datasets
    import pyarrow.parquet as pq

    units: dict[str, list[dict[str, Any]]] = defaultdict(list)
    for config, unit in [(CLEAN, "benchmark"), *((p, "benchmark") for p in PATTERN_CONFIGS), (MEMORY_BANK, "memory")]:
        # Parquet stores a class label as its index: back to the name the build wrote.
        labels = {
            name: feature
            for name, feature in features("memory_bank" if config == MEMORY_BANK else "instruction").items()
            if isinstance(feature, datasets.ClassLabel)
        }
        for files in data_files(config).values():
            for relative in files:
                path = folder / relative
                if not path.is_file():
                    raise ValueError(f"{path}: missing; {folder} is not a complete TALK-Dem dataset folder")
                for row in pq.read_table(path).to_pylist():
                    row.update({name: feature.int2str(row[name]) for name, feature in labels.items()})
                    units[f"{unit}:{row['task_id']}"].append(row)
    return dict(units)


def replay(source: Path, out: Path, tasks_folder: Path | None = None, margin: float | None = None) -> dict[str, Any]:
    """Rebuild `source` into `out` (the build's statistics are returned); `tasks_folder` holds
    `tasks/*.jsonl`, what the build generated from (default: `data/`, as for the build).

    `margin`, for a ranked build, chooses again from the recorded scores with another ranking margin
    (`builders.generation.ranking.choose`) instead of the build's own: what `--rank-margin` would have built,
    without the model."""
    stats_path = source / "build_stats.json"
    try:
        info = json.loads(stats_path.read_text())["build"]
    except (OSError, ValueError, KeyError) as exc:
        raise ValueError(f"{stats_path}: no build settings to replay ({exc})") from None
    if "llm" in info["generator"]:
        raise ValueError(f"{stats_path}: an LLM build ({info['generator']}) cannot be replayed without its model")
    gen = get_generator(info["generator"])
    if gen.prompt_version != info["prompt_version"]:
        raise ValueError(
            f"{stats_path}: built with {info['prompt_version']}, the generator '{info['generator']}' is now "
            f"{gen.prompt_version}"
        )
    if hasattr(gen, "candidates"):
        gen.candidates = info["candidates"]
    if margin is not None:
        checked_margin(margin)  # before the folder is read: a bad margin is the caller's, not the data's
        if not info.get("rank_model"):
            raise ValueError(f"{stats_path}: an unranked build has no scores to choose from with a margin")
        info = {**info, "rank_margin": margin}
    chosen_within = info.get("rank_margin") or 0.0
    benchmark, memory = (_built_from(source, name, tasks_folder or data_dir()) for name in ("benchmark", "memory"))
    recorded = recorded_rows(source)
    check_output_folder(out)
    units = {}
    for unit, tasks in (("benchmark", benchmark), ("memory", memory)):
        for task in tasks:
            key = f"{unit}:{task.task_id}"
            if key not in recorded:
                raise ValueError(f"{source}: no rows for {unit} task {task.task_id}")
            ranker = RecordedRanker.from_rows(recorded[key], chosen_within)
            units[key] = build_unit(gen, task, info["seed"], ranker=ranker)
    return write_dataset(out, benchmark, memory, units, info)[1]


def _built_from(source: Path, name: str, tasks_folder: Path) -> list[Task]:
    """The tasks a build generated from, in its order: those its task table lists (a `--limit` build lists
    the first N), read from the task files."""
    import pyarrow.parquet as pq

    (relative,) = data_files(TASKS)[name]
    path = source / relative
    if not path.is_file():
        raise ValueError(f"{path}: missing; {source} is not a complete TALK-Dem dataset folder")
    by_id = {task.task_id: task for task in load_tasks(TaskSet(name), tasks_folder)}
    listed = pq.read_table(path, columns=["task_id"]).column("task_id").to_pylist()
    unknown = [task_id for task_id in listed if task_id not in by_id]
    if unknown:
        raise ValueError(f"{path}: {len(unknown)} tasks not in {tasks_folder}/tasks ({unknown[0]}, ...)")
    return [by_id[task_id] for task_id in listed]
