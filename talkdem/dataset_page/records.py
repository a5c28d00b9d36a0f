"""The tasks a sample page shows, read from a dataset folder's instruction configs, and the sample drawn."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from talkdem.schema import CLEAN, PATTERN_CONFIGS

__all__ = ["PageTask", "PageVariant", "load_page_tasks", "sample_tasks"]


@dataclass(frozen=True)
class PageVariant:
    """One pattern variant of a task, as the page shows it."""

    pattern: str
    level: int
    text: str
    passed: bool
    """Whether the utterance passed verification (a failing one is kept with its failed checks)."""
    failed_checks: tuple[str, ...]


@dataclass(frozen=True)
class PageTask:
    """One benchmark task: its ALFRED seed, its clean control and its pattern variants."""

    task_id: str
    task_type: str
    target: str
    """The target object type (`pddl_params.object_target`)."""
    seed: str
    clean: str
    variants: tuple[PageVariant, ...]
    generator: str
    prompt_version: str


def _variant(row: dict[str, Any]) -> PageVariant:
    verification = row.get("verification") or {}
    return PageVariant(
        pattern=str(row["pattern"]),
        level=int(row["level"]),
        text=str(row["instruction"]),
        passed=bool(verification.get("passed", True)),
        failed_checks=tuple(str(c) for c in verification.get("failed_checks") or ()),
    )


def load_page_tasks(folder: Path) -> list[PageTask]:
    """Every task of the dataset in `folder` that has a clean control, in task-id order."""
    from talkdem.instructions import config_rows

    variants: dict[str, list[PageVariant]] = {}
    for config in PATTERN_CONFIGS:
        for row in config_rows(config, folder):
            variants.setdefault(str(row["task_id"]), []).append(_variant(row))
    tasks = []
    for row in config_rows(CLEAN, folder):
        task_id = str(row["task_id"])
        params = row.get("pddl_params") or {}
        found = sorted(variants.get(task_id, []), key=lambda v: (PATTERN_CONFIGS.index(v.pattern), v.level))
        tasks.append(
            PageTask(
                task_id=task_id,
                task_type=str(row["task_type"]),
                target=str(params.get("object_target") or ""),
                seed=str(row["seed_instruction"]),
                clean=str(row["instruction"]),
                variants=tuple(found),
                generator=str(row.get("generator") or ""),
                prompt_version=str(row.get("prompt_version") or ""),
            )
        )
    if not tasks:
        raise ValueError(f"{folder}: the dataset has no clean controls (is it a TALK-Dem dataset folder?)")
    return sorted(tasks, key=lambda t: t.task_id)


def sample_tasks(tasks: Sequence[PageTask], per_type: int | None) -> list[PageTask]:
    """`per_type` tasks of each task type, evenly spaced in task-id order (no randomness: the same data give the
    same page), grouped by task type; `None` keeps every task."""
    if per_type is not None and per_type < 1:
        raise ValueError(f"tasks per task type must be at least 1, got {per_type}")
    chosen = []
    for task_type in sorted({t.task_type for t in tasks}):
        members = sorted((t for t in tasks if t.task_type == task_type), key=lambda t: t.task_id)
        if per_type is None or per_type >= len(members):
            chosen += members
            continue
        # The middle of each of `per_type` equal stretches: spread over the type, not its first few ids.
        chosen += [members[(2 * i + 1) * len(members) // (2 * per_type)] for i in range(per_type)]
    return chosen
