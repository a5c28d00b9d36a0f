"""CARE's retrieval diagnostics: what the memory item CARE puts next to a query has in common with it.

Every benchmark instruction (the 300 clean controls and the 4,500 pattern variants) is a query; CARE's own
retrieval (`care.strategy.ContextAwareRetrieval`: all-MiniLM-L6-v2, cosine top-k, ties to the lower index)
returns its most similar memory item. Counted per query: the item has the query's pattern, the query task's
target object type (`pddl_params.object_target`), its ALFRED task type, its ALFRED task (`task_name`: goal,
objects, floor plan; zero once the memory bank is disjoint at the task level, `MEMORY_RULE`).

Everything is read from a dataset folder (the instruction configs, the `memory_bank` rows and the `tasks`
config for the task names), so the figures describe the memory bank as built, not the task files that a later
build will read. `talkdem retrieval --data DIR` writes them to `DIR/selection/retrieval.json`, keyed by a
digest of the files read; the card shows them only while that digest matches.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from talkdem.files import replace_file
from talkdem.schema import CLEAN, MEMORY_BANK, PATTERN_CONFIGS, PATTERNS, TASKS, data_files

__all__ = [
    "ALL_VARIANTS",
    "QueryLabels",
    "RetrievalRow",
    "compute_retrieval",
    "memory_bank_section",
    "retrieval_file",
    "retrieval_inputs_digest",
    "retrieval_table",
    "top1_agreement",
    "write_retrieval",
]

Encoder = Callable[[Sequence[str]], NDArray[np.float64]]

ALL_VARIANTS = "all variants"
"""The group of the 4,500 pattern variants (the clean controls are a group of their own)."""

_RETRIEVAL_FILE = "selection/retrieval.json"


@dataclass(frozen=True)
class QueryLabels:
    """What a query or a memory item is compared on."""

    pattern: str
    """`clean` or the pattern's config name."""
    task_type: str
    target: str
    """The task's target object type (`pddl_params.object_target`)."""
    task_name: str
    """ALFRED's task name: task type, objects and floor plan."""


@dataclass(frozen=True)
class RetrievalRow:
    """One group of queries: how often the top-1 memory item shares each label with its query."""

    group: str
    """`all variants`, a pattern's config name, or `clean`."""
    queries: int
    same_pattern: float
    same_target: float
    same_task_type: float
    same_alfred_task: float


def _share(pairs: Sequence[tuple[QueryLabels, QueryLabels]], field: str) -> float:
    same = sum(1 for query, item in pairs if getattr(query, field) == getattr(item, field))
    return round(same / len(pairs), 4)


def top1_agreement(queries: Sequence[QueryLabels], retrieved: Sequence[QueryLabels]) -> list[RetrievalRow]:
    """Shares per group, `retrieved[i]` being the top-1 item of `queries[i]`: all variants, then each pattern
    in the schema's order, then the clean controls (groups without queries are left out)."""
    if len(queries) != len(retrieved):
        raise ValueError(f"{len(queries)} queries but {len(retrieved)} retrieved items")
    pairs = list(zip(queries, retrieved, strict=True))
    groups = [(ALL_VARIANTS, [p for p in pairs if p[0].pattern != CLEAN])]
    groups += [(name, [p for p in pairs if p[0].pattern == name]) for name in (*PATTERN_CONFIGS, CLEAN)]
    rows = []
    for name, members in groups:
        if not members:
            continue
        rows.append(
            RetrievalRow(
                group=name,
                queries=len(members),
                same_pattern=_share(members, "pattern"),
                same_target=_share(members, "target"),
                same_task_type=_share(members, "task_type"),
                same_alfred_task=_share(members, "task_name"),
            )
        )
    return rows


def retrieval_file(folder: Path) -> Path:
    return folder / _RETRIEVAL_FILE


def retrieval_inputs_digest(folder: Path) -> str:
    """sha256 over the Parquet files the diagnostics read (names and bytes): a rebuild changes it."""
    digest = hashlib.sha256()
    for config in (CLEAN, *PATTERN_CONFIGS, MEMORY_BANK, TASKS):
        for paths in data_files(config).values():
            for relative in paths:
                digest.update(relative.encode() + b"\0" + (folder / relative).read_bytes())
    return digest.hexdigest()


def _labels(row: dict[str, Any], task_names: dict[str, str]) -> QueryLabels:
    task_id = row["task_id"]
    if task_id not in task_names:
        raise ValueError(f"task {task_id} (row {row['id']}) is not in the dataset's `tasks` config")
    return QueryLabels(
        pattern=str(row["pattern"]),
        task_type=str(row["task_type"]),
        target=str(row["pddl_params"]["object_target"]),
        task_name=task_names[task_id],
    )


def compute_retrieval(folder: Path, encode: Encoder | None = None) -> dict[str, Any]:
    """The diagnostics of the dataset in `folder`, with CARE's retrieval; `encode` defaults to CARE's own
    cached all-MiniLM-L6-v2 (tests pass a small stand-in)."""
    from care.strategy import ContextAwareRetrieval
    from talkdem.instructions import config_rows, load_memory_bank

    task_names = {str(r["task_id"]): str(r["task_name"]) for r in config_rows(TASKS, folder)}
    bank_rows = {str(r["id"]): r for r in config_rows(MEMORY_BANK, folder)}
    queries = [r for config in (CLEAN, *PATTERN_CONFIGS) for r in config_rows(config, folder)]
    if not bank_rows or not queries:
        raise ValueError(f"{folder}: the dataset has no memory bank rows or no benchmark instructions")
    # CARE's retrieval over CARE's view of the bank (its item order decides ties), labelled from the same rows.
    care = ContextAwareRetrieval(memory=load_memory_bank(folder), k=1, encode=encode)
    top = care.retrieve([str(r["instruction"]) for r in queries])
    rows = top1_agreement(
        [_labels(r, task_names) for r in queries],
        [_labels(bank_rows[items[0].id], task_names) for items in top],
    )
    return {
        "encoder": "sentence-transformers/all-MiniLM-L6-v2" if encode is None else "given",
        "queries": len(queries),
        "memory_items": len(bank_rows),
        "inputs_sha256": retrieval_inputs_digest(folder),
        "rows": [asdict(r) for r in rows],
    }


def write_retrieval(folder: Path, report: dict[str, Any]) -> Path:
    path = retrieval_file(folder)
    path.parent.mkdir(parents=True, exist_ok=True)
    replace_file(path, json.dumps(report, indent=2) + "\n")
    return path


def _group_name(group: str) -> str:
    if group == ALL_VARIANTS:
        return "All 15 variants"
    if group == CLEAN:
        return "Clean controls"
    return PATTERNS[group].name


def retrieval_table(rows: Sequence[RetrievalRow]) -> str:
    """The diagnostics as a Markdown table (shares in percent)."""
    lines = [
        "| Queries | n | Same pattern | Same target object | Same task type | Same ALFRED task |",
        "| --- | ---: | ---: | ---: | ---: | ---: |",
    ]
    for r in rows:
        shares = " | ".join(
            f"{100 * c:.1f}%" for c in (r.same_pattern, r.same_target, r.same_task_type, r.same_alfred_task)
        )
        lines.append(f"| {_group_name(r.group)} | {r.queries:,} | {shares} |")
    return "\n".join(lines)


def memory_bank_section(folder: Path) -> str:
    """The card's fragment on the memory bank: the disjointness rule, then CARE's retrieval diagnostics if
    `selection/retrieval.json` was computed on this very build (else the command that computes them)."""
    from builders.selection.pipeline import MEMORY_RULE

    text = "The memory-bank tasks were selected from the remaining candidates by the same procedure. " + MEMORY_RULE
    path = retrieval_file(folder)
    command = "`talkdem retrieval`"
    if not path.is_file():
        return text + f"\n\nCARE's retrieval diagnostics are not computed for this build yet: run {command}."
    try:
        report = json.loads(path.read_text(encoding="utf-8"))
        rows = [RetrievalRow(**row) for row in report["rows"]]
        current = report["inputs_sha256"] == retrieval_inputs_digest(folder)
    except (OSError, ValueError, KeyError, TypeError) as exc:
        raise ValueError(f"{path}: not a retrieval report ({exc}); rerun `talkdem retrieval`") from None
    if not current:
        return text + (
            f"\n\nThe retrieval diagnostics in `{_RETRIEVAL_FILE}` were computed on another build of the "
            f"data; rerun {command}."
        )
    leak = (
        "No query retrieves an item of its own ALFRED task, as the rule requires."
        if all(r.same_alfred_task == 0 for r in rows)
        else "Some queries retrieve an item of their own ALFRED task: this memory bank was built from task files "
        "that break the rule above (built before it, or from other task files)."
    )
    return text + (
        "\n\n**What CARE retrieves.** Each of the benchmark's instructions is a query; the table counts how often "
        "the single most similar memory item (CARE's own retrieval, all-MiniLM-L6-v2 cosine similarity over "
        f"the {report['memory_items']:,} memory items) has the query's pattern, the target object type of the "
        "query's task, its task type, and its ALFRED task (goal, objects and floor plan). A demonstration of the "
        "same pattern shows the planner how that pattern is resolved; "
        "one with the same target object shows a plan for that very object. Computed by `talkdem retrieval` "
        f"(`{_RETRIEVAL_FILE}`). {leak}\n\n" + retrieval_table(rows)
    )
