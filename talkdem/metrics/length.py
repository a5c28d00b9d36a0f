"""Plan length of jointly successful clean/transformed pairs (appendix "Plan Length Analysis").

Each successful pattern episode whose clean twin (same task, same run) also succeeded is one pair; levels
are pooled. Delta is transformed minus clean; its test clusters standard errors by task.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from talkdem.metrics.episodes import EpisodeResult
from talkdem.metrics.stats import TestResult, clustered_mean_test
from talkdem.schema import CLEAN, PATTERN_CONFIGS

__all__ = ["ALL", "PlanLengthRow", "plan_length_pairs"]

ALL = "all"


@dataclass(frozen=True)
class PlanLengthRow:
    """Jointly successful pairs: their count, mean clean and transformed lengths, and the paired test."""

    n: int
    clean: float
    transformed: float
    delta: float
    test: TestResult

    def to_json(self) -> dict[str, object]:
        means = {"clean": self.clean, "transformed": self.transformed, "delta": self.delta}
        nan_free = {k: (None if math.isnan(v) else v) for k, v in means.items()}
        return {"n": self.n, **nan_free, "test": self.test.to_json()}


def plan_length_pairs(results: Sequence[EpisodeResult]) -> dict[str, PlanLengthRow]:
    """pattern (and `all`) -> PlanLengthRow."""
    clean = {(r.run, r.task_id): r for r in results if r.condition.pattern == CLEAN and r.success}
    pairs: dict[str, list[tuple[float, float, str]]] = {p: [] for p in (*PATTERN_CONFIGS, ALL)}
    for result in results:
        twin = clean.get((result.run, result.task_id))
        if result.condition.pattern == CLEAN or not result.success or twin is None:
            continue
        pair = (float(twin.plan_length), float(result.plan_length), f"{result.run}\x00{result.task_id}")
        pairs[result.condition.pattern].append(pair)
        pairs[ALL].append(pair)
    rows = {}
    for name, items in pairs.items():
        if not items:
            rows[name] = PlanLengthRow(0, math.nan, math.nan, math.nan, TestResult(math.nan, math.nan, math.nan, 0))
            continue
        clean_lengths = [c for c, _, _ in items]
        transformed = [t for _, t, _ in items]
        test = clustered_mean_test([t - c for c, t, _ in items], [k for _, _, k in items])
        mean_clean = sum(clean_lengths) / len(items)
        mean_transformed = sum(transformed) / len(items)
        rows[name] = PlanLengthRow(len(items), mean_clean, mean_transformed, mean_transformed - mean_clean, test)
    return rows
