"""Select the 300 benchmark tasks and the 100 memory-bank tasks from the seed pool.

Paper, appendix "Diversity Sampling": one instruction per ALFRED trial (803 candidates), embedded with
all-MiniLM-L6-v2; within each task type, greedy max-min sampling picks 50 trials. The memory bank takes
100 further trials from the remaining candidates by the same procedure, spread over the six types.

The memory bank is disjoint from the benchmark at the level of the ALFRED task, not only of the trial
(`MEMORY_RULE`): ALFRED records several trials (crowd demonstrations) of one task, a `task_name` such as
`pick_and_place_simple-SoapBar-None-GarbageCan-416` (task type, target, movable receptacle, destination, floor
plan), and their reference plans are mostly identical. A memory candidate is dropped when its `task_name` is
that of a benchmark task, or when its seed instruction, normalised (`normalise_seed_text`), is that of a
benchmark task. The benchmark is selected first, from every candidate, so this rule cannot change it.
"""

from __future__ import annotations

import json
import re
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from builders.selection.maxmin import greedy_max_min, mean_pairwise_similarity, random_subset_similarity
from talkdem.paths import data_dir
from talkdem.seeds.records import SeedTask
from talkdem.sim import run_plan
from talkdem.sim.initial_state import fixture_pool
from talkdem.tasks import Task, TaskSet, make_task, reference_plan, task_file, write_tasks

__all__ = [
    "MEMORY_RULE",
    "DiversityRow",
    "Selection",
    "SelectionSettings",
    "diversity_file",
    "format_diversity_table",
    "load_diversity",
    "memory_quotas",
    "normalise_seed_text",
    "one_seed_per_trial",
    "select_tasks",
    "shares_benchmark_task",
    "write_selection",
]

Encoder = Callable[[Sequence[str]], NDArray[np.float64]]

MEMORY_RULE = (
    "No memory-bank task shares an ALFRED task with a benchmark task: a candidate trial is left out of the "
    "memory bank's candidates when its ALFRED task name (task type, target object, movable receptacle, "
    "destination and floor plan, e.g. `pick_and_place_simple-SoapBar-None-GarbageCan-416`) is that of a "
    "benchmark task, or when its seed instruction is that of a benchmark task after normalisation (lower "
    "case, punctuation removed, whitespace collapsed). Other trials of a benchmark task are other crowd "
    "demonstrations of the same goal in the same scene, mostly with the same reference plan: retrieving one "
    "would hand CARE the answer. The benchmark is selected first, so the rule does not change it."
)
"""The rule, as the dataset card states it."""


@dataclass(frozen=True)
class SelectionSettings:
    """Everything that determines the selection besides the seed pool itself."""

    encoder: str = "sentence-transformers/all-MiniLM-L6-v2"
    per_type: int = 50
    memory_total: int = 100
    random_draws: int = 50
    random_seed: int = 0


@dataclass(frozen=True)
class DiversityRow:
    """One row of the paper's diversity table (Table "Semantic diversity of the selected task set")."""

    task_type: str
    candidates: int
    random: float
    """Mean pairwise similarity of `per_type` random trials, averaged over `random_draws` draws."""
    random_std: float
    selected: float
    """Mean pairwise similarity of the trials chosen by greedy max-min sampling."""
    memory_tasks: int
    memory_selected: float


@dataclass(frozen=True)
class Selection:
    benchmark: tuple[SeedTask, ...]
    memory: tuple[SeedTask, ...]
    diversity: tuple[DiversityRow, ...]
    settings: SelectionSettings
    fixtures: dict[str, frozenset[str]]
    """Fixed-object ids per floor plan, pooled over every seed (stored with each task)."""
    excluded_from_memory: tuple[str, ...] = ()
    """Trials left out of the memory-bank candidates because their reference plan fails in the simulator."""
    shared_with_benchmark: tuple[str, ...] = ()
    """Trials left out of the memory-bank candidates because they share an ALFRED task or a seed text with a
    benchmark task (`MEMORY_RULE`)."""

    def task(self, seed: SeedTask, task_set: TaskSet) -> Task:
        return make_task(seed, task_set, tuple(self.fixtures.get(seed.floor_plan, ())))


def one_seed_per_trial(seeds: Sequence[SeedTask]) -> list[SeedTask]:
    """Keep the annotation with the lowest `repeat_idx` of each trial, sorted by task type then trial id."""
    best: dict[str, SeedTask] = {}
    for seed in seeds:
        kept = best.get(seed.task_id)
        if kept is None or seed.repeat_idx < kept.repeat_idx:
            best[seed.task_id] = seed
    return sorted(best.values(), key=lambda s: (s.task_type, s.task_id))


def normalise_seed_text(text: str) -> str:
    """The seed instruction as compared by `MEMORY_RULE`: lower case, words and digits only, single spaces."""
    return " ".join(re.findall(r"[a-z0-9]+", text.casefold()))


def shares_benchmark_task(candidate: SeedTask, benchmark: Sequence[SeedTask]) -> bool:
    """Whether `candidate` has the ALFRED task name or the normalised seed text of a benchmark task."""
    names = {b.task_name for b in benchmark}
    texts = {normalise_seed_text(b.instruction) for b in benchmark}
    return candidate.task_name in names or normalise_seed_text(candidate.instruction) in texts


def memory_quotas(task_types: Sequence[str], total: int) -> dict[str, int]:
    """Split `total` as evenly as possible; the first types in sorted order take the remainder."""
    ordered = sorted(task_types)
    base, extra = divmod(total, len(ordered))
    return {t: base + (1 if i < extra else 0) for i, t in enumerate(ordered)}


def select_tasks(
    seeds: Sequence[SeedTask], encode: Encoder | None = None, settings: SelectionSettings | None = None
) -> Selection:
    """Run the selection; `encode` defaults to all-MiniLM-L6-v2 (tests may pass a small stand-in)."""
    settings = settings or SelectionSettings()
    if encode is None:
        from talkdem.embeddings import encode as minilm_encode

        encode = minilm_encode
    candidates = one_seed_per_trial(seeds)
    fixtures = fixture_pool(seeds)
    # A memory item is a demonstration of a resolved task: its reference plan must execute. (The benchmark
    # is selected from every candidate, as in the paper; a test checks that its 300 plans all succeed.)
    runs_clean = {
        c.task_id: run_plan(
            make_task(c, TaskSet.MEMORY, tuple(fixtures.get(c.floor_plan, ()))), reference_plan(c)
        ).success
        for c in candidates
    }
    embeddings = encode([c.instruction for c in candidates])
    task_types = sorted({c.task_type for c in candidates})
    quotas = memory_quotas(task_types, settings.memory_total)
    groups = {t: [i for i, c in enumerate(candidates) if c.task_type == t] for t in task_types}
    similarities: dict[str, NDArray[np.float64]] = {}
    chosen_by_type: dict[str, list[int]] = {}
    for task_type, members in groups.items():
        if len(members) < settings.per_type + quotas[task_type]:
            raise ValueError(
                f"task type {task_type}: {len(members)} candidate trials, need {settings.per_type} "
                f"benchmark + {quotas[task_type]} memory tasks"
            )
        group = embeddings[members]
        similarities[task_type] = group @ group.T
        chosen_by_type[task_type] = greedy_max_min(similarities[task_type], settings.per_type)
    benchmark = [candidates[groups[t][i]] for t in task_types for i in chosen_by_type[t]]
    # The whole benchmark is known before any memory task is drawn: a seed text may recur under another type.
    chosen_ids = {b.task_id for b in benchmark}
    shared = {c.task_id for c in candidates if c.task_id not in chosen_ids and shares_benchmark_task(c, benchmark)}
    memory: list[SeedTask] = []
    rows = []
    for task_type in task_types:
        members, chosen, similarity = groups[task_type], chosen_by_type[task_type], similarities[task_type]
        taken = set(chosen)
        rest = [
            i
            for i in range(len(members))
            if i not in taken
            and runs_clean[candidates[members[i]].task_id]
            and candidates[members[i]].task_id not in shared
        ]
        if len(rest) < quotas[task_type]:
            raise ValueError(
                f"task type {task_type}: {len(rest)} memory candidates left after the benchmark, failing plans and "
                f"shared ALFRED tasks, need {quotas[task_type]}"
            )
        rest_similarity = similarity[np.ix_(rest, rest)]
        memory_chosen = [rest[i] for i in greedy_max_min(rest_similarity, quotas[task_type])]
        random_mean, random_std = random_subset_similarity(
            similarity, settings.per_type, settings.random_draws, settings.random_seed
        )
        rows.append(
            DiversityRow(
                task_type=task_type,
                candidates=len(members),
                random=round(random_mean, 4),
                random_std=round(random_std, 4),
                selected=round(mean_pairwise_similarity(similarity, chosen), 4),
                memory_tasks=len(memory_chosen),
                memory_selected=round(mean_pairwise_similarity(similarity, memory_chosen), 4),
            )
        )
        memory += [candidates[members[i]] for i in memory_chosen]
    excluded = tuple(sorted(c.task_id for c in candidates if not runs_clean[c.task_id]))
    return Selection(tuple(benchmark), tuple(memory), tuple(rows), settings, fixtures, excluded, tuple(sorted(shared)))


def diversity_file(folder: Path | None = None) -> Path:
    return data_dir(folder) / "selection" / "diversity.json"


def format_diversity_table(rows: Sequence[DiversityRow]) -> str:
    """The paper's diversity table as Markdown (lower similarity = more diverse)."""
    lines = [
        "| Task type | Candidates | Random | Selected | Memory tasks | Memory selected |",
        "|---|---:|---:|---:|---:|---:|",
    ]
    for r in rows:
        lines.append(
            f"| {r.task_type} | {r.candidates} | {r.random:.3f} ± {r.random_std:.3f} | {r.selected:.3f} "
            f"| {r.memory_tasks} | {r.memory_selected:.3f} |"
        )
    return "\n".join(lines)


def write_selection(selection: Selection, folder: Path | None = None) -> list[Path]:
    """Write the task sets and the diversity table under `data/`; returns the paths written."""
    written = []
    for task_set, seeds in ((TaskSet.BENCHMARK, selection.benchmark), (TaskSet.MEMORY, selection.memory)):
        path = task_file(task_set, folder)
        write_tasks([selection.task(seed, task_set) for seed in seeds], path)
        written.append(path)
    table_json = diversity_file(folder)
    table_json.parent.mkdir(parents=True, exist_ok=True)
    payload = {
        "settings": asdict(selection.settings),
        "rows": [asdict(r) for r in selection.diversity],
        "excluded_from_memory": list(selection.excluded_from_memory),
        "memory_rule": MEMORY_RULE,
        "excluded_shared_with_benchmark": list(selection.shared_with_benchmark),
    }
    table_json.write_text(json.dumps(payload, indent=2) + "\n")
    table_md = table_json.with_suffix(".md")
    table_md.write_text(
        "# Semantic diversity of the selected task set\n\n"
        "Mean pairwise cosine similarity (all-MiniLM-L6-v2) of seed instructions; lower is more diverse.\n"
        f"Random: {selection.settings.per_type} random trials, mean ± sd over {selection.settings.random_draws} "
        "draws. Selected: greedy max-min sampling.\n\n"
        + format_diversity_table(selection.diversity)
        + "\n\n## The memory bank's candidates\n\n"
        + MEMORY_RULE
        + f"\n\n{len(selection.shared_with_benchmark)} trials were left out by this rule and "
        f"{len(selection.excluded_from_memory)} because their reference plan fails in the simulator "
        "(both lists are in `diversity.json`).\n"
    )
    return [*written, table_json, table_md]


def load_diversity(folder: Path | None = None) -> list[DiversityRow]:
    """The diversity table saved by the last `write_selection`."""
    path = diversity_file(folder)
    if not path.is_file():
        raise FileNotFoundError(f"{path}: no diversity table (run `talkdem select --write`)")
    return [DiversityRow(**row) for row in json.loads(path.read_text())["rows"]]
