"""Seed selection: greedy max-min sampling over MiniLM sentence embeddings."""

from builders.selection.maxmin import greedy_max_min, mean_pairwise_similarity, random_subset_similarity
from builders.selection.pipeline import (
    MEMORY_RULE,
    DiversityRow,
    Selection,
    SelectionSettings,
    format_diversity_table,
    load_diversity,
    memory_quotas,
    normalise_seed_text,
    one_seed_per_trial,
    select_tasks,
    shares_benchmark_task,
    write_selection,
)

__all__ = [
    "MEMORY_RULE",
    "DiversityRow",
    "Selection",
    "SelectionSettings",
    "format_diversity_table",
    "greedy_max_min",
    "load_diversity",
    "mean_pairwise_similarity",
    "memory_quotas",
    "normalise_seed_text",
    "one_seed_per_trial",
    "random_subset_similarity",
    "select_tasks",
    "shares_benchmark_task",
    "write_selection",
]
