"""`Scores`: every measurement of one run (or one set of plans), and the functions that compute it."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from talkdem.metrics.episodes import (
    EpisodeResult,
    ScoringInputError,
    execute_plans,
    pair_predictions,
    results_from_run,
)
from talkdem.metrics.errors import ErrorType, classify_error
from talkdem.metrics.hazards import HazardCounts, introduced_hazards
from talkdem.metrics.length import PlanLengthRow, plan_length_pairs
from talkdem.metrics.rates import MEASURES, measures, outcome_matrix, task_retention
from talkdem.metrics.stats import BOOTSTRAP_SEED, TestResult, bootstrap_ci, check_resamples, paired_ttest
from talkdem.schema import CLEAN, CONDITIONS, PATTERN_CONFIGS, Condition
from talkdem.sim import DEFAULT_MAX_STEPS

__all__ = [
    "ClassifiedError",
    "Scores",
    "compare_retention",
    "compute_scores",
    "error_cases",
    "missing_clean_twins",
    "score_plans",
    "score_predictions",
    "score_run",
]


@dataclass(frozen=True)
class ClassifiedError:
    """A pattern episode that failed although its clean twin succeeded, with its primary error type."""

    instruction_id: str
    run: str
    condition: Condition
    type: ErrorType
    reason: str


@dataclass(frozen=True)
class Scores:
    """Every measurement of one set of episodes. Rates are fractions (0-1); NaN where undefined."""

    n_episodes: int
    n_tasks: int
    success_rate: dict[str, float]
    """condition key (`clean`, `intrusion:3`) -> SR, plus each pattern (mean over levels) and `average`
    (mean over the 15 pattern conditions)."""
    sr_change: dict[str, float]
    """pattern -> SR of the pattern (mean over levels) minus clean SR."""
    sr_change_test: dict[str, TestResult]
    """pattern -> two-sided paired t-test, per task: mean over levels vs the clean outcome."""
    retention: dict[str, float] | None
    """`<pattern>:<level>`, each pattern and `average` -> clean-conditioned retention; None if not asked."""
    clean_successes: int
    task_retention: dict[str, dict[str, float]]
    """`all` and each pattern -> task id (`run:task` when runs are pooled) -> per-task retention, for the
    tasks solved under clean."""
    hazards: HazardCounts
    plan_length: dict[str, PlanLengthRow]
    errors: tuple[ClassifiedError, ...]
    intervals: dict[str, tuple[float, float]]
    """`sr/<key>` and `retention/<key>` -> 95% percentile bootstrap interval over tasks."""
    episodes: tuple[EpisodeResult, ...] = field(repr=False, compare=False, default=())
    without_clean_twin: tuple[str, ...] = ()
    """Pattern episodes whose task has no clean episode in the same run, when they left retention out
    (`compute_scores` with `retention=None`): `retention` is None for this reason, not because none was asked."""

    def error_counts(self, pattern: str | None = None) -> dict[ErrorType, int]:
        counts = dict.fromkeys(ErrorType, 0)
        for error in self.errors:
            if pattern is None or error.condition.pattern == pattern:
                counts[error.type] += 1
        return counts

    def flat(self) -> dict[str, float | int | None]:
        """One flat dict (the evaluate module's return value); NaN becomes None."""
        out: dict[str, float | int | None] = {"n_episodes": self.n_episodes, "n_tasks": self.n_tasks}
        out.update({f"success_rate/{k}": _clean(v) for k, v in self.success_rate.items()})
        for pattern in PATTERN_CONFIGS:
            out[f"sr_change/{pattern}"] = _clean(self.sr_change[pattern])
            out[f"sr_change_p/{pattern}"] = _clean(self.sr_change_test[pattern].p_value)
        if self.retention is not None:
            out.update({f"retention/{k}": _clean(v) for k, v in self.retention.items()})
            out["clean_successes"] = self.clean_successes
        for category, row in self.hazards.by_category.items():
            out.update({f"hazards/{category}/{p}": n for p, n in row.items()})
        out.update({f"hazard_cases/{p}": n for p, n in self.hazards.distinct_cases.items()})
        out["hazard_cases"] = self.hazards.total_cases
        for name, lengths in self.plan_length.items():
            out[f"plan_length/{name}/n"] = lengths.n
            out[f"plan_length/{name}/clean"] = _clean(lengths.clean)
            out[f"plan_length/{name}/transformed"] = _clean(lengths.transformed)
            out[f"plan_length/{name}/delta"] = _clean(lengths.delta)
            out[f"plan_length/{name}/p"] = _clean(lengths.test.p_value)
        out.update({f"errors/{t.value}": n for t, n in self.error_counts().items()})
        for key, (low, high) in self.intervals.items():
            out[f"ci_low/{key}"] = _clean(low)
            out[f"ci_high/{key}"] = _clean(high)
        return out

    def to_json(self) -> dict[str, Any]:
        return {
            "n_episodes": self.n_episodes,
            "n_tasks": self.n_tasks,
            "success_rate": {k: _clean(v) for k, v in self.success_rate.items()},
            "sr_change": {k: _clean(v) for k, v in self.sr_change.items()},
            "sr_change_test": {k: v.to_json() for k, v in self.sr_change_test.items()},
            "retention": None if self.retention is None else {k: _clean(v) for k, v in self.retention.items()},
            "clean_successes": self.clean_successes,
            "hazards": self.hazards.to_json(),
            "plan_length": {k: v.to_json() for k, v in self.plan_length.items()},
            "errors": {t.value: n for t, n in self.error_counts().items()},
            "errors_by_pattern": {p: {t.value: n for t, n in self.error_counts(p).items()} for p in PATTERN_CONFIGS},
            "error_cases": [
                {"instruction_id": e.instruction_id, "type": e.type.value, "reason": e.reason} for e in self.errors
            ],
            "intervals": {k: [_clean(lo), _clean(hi)] for k, (lo, hi) in self.intervals.items()},
        }


def _clean(value: float) -> float | None:
    return None if math.isnan(value) else float(value)


def missing_clean_twins(results: Sequence[EpisodeResult]) -> list[str]:
    """The pattern episodes whose task has no clean episode in the same run: retention cannot be measured
    while there is one (`compute_scores` refuses them or, by default, leaves retention out)."""
    have_clean = {(r.run, r.task_id) for r in results if r.condition.pattern == CLEAN}
    patterned = [r for r in results if r.condition.pattern != CLEAN]
    return [r.instruction_id for r in patterned if (r.run, r.task_id) not in have_clean]


def _check_clean_twins(results: Sequence[EpisodeResult]) -> None:
    orphans = missing_clean_twins(results)
    if orphans:
        # Names the Python argument: the CLI never gets here (`talkdem report` scores such runs without retention).
        raise ScoringInputError(
            "retention needs the clean instruction of each task; these pattern ids have no clean twin "
            "(add `<task_id>:clean` plans, or call with retention=False to score without retention)",
            orphans,
        )


def error_cases(results: Sequence[EpisodeResult]) -> tuple[ClassifiedError, ...]:
    """Classify every pattern episode that failed while its clean twin (same run and task) succeeded."""
    from talkdem.tasks import get_task

    solved_clean = {(r.run, r.task_id) for r in results if r.condition.pattern == CLEAN and r.success}
    out = []
    for result in results:
        if result.condition.pattern == CLEAN or result.success or (result.run, result.task_id) not in solved_clean:
            continue
        if result.trace is None:
            continue
        found = classify_error(get_task(result.task_id), result.trace)
        if found is not None:
            out.append(ClassifiedError(result.instruction_id, result.run, result.condition, found.type, found.reason))
    return tuple(out)


def compute_scores(
    results: Sequence[EpisodeResult],
    *,
    retention: bool | None = None,
    bootstrap: int = 1000,
    seed: int = BOOTSTRAP_SEED,
    classify_errors: bool = True,
) -> Scores:
    """Every measurement of `results` (episodes of one run, or pooled runs told apart by `run`).
    `bootstrap`: 0 (no intervals) or at least `MIN_RESAMPLES` resamples; anything else is a `ValueError`.
    `retention`: True measures it and refuses pattern episodes without their clean twin; False leaves it out;
    None (the default, what `talkdem report` uses) measures it when every pattern episode has its clean twin
    and otherwise leaves it out, naming those episodes in `without_clean_twin` (a run of pattern conditions
    only, `--conditions intrusion:3`, still has its success rates)."""
    bootstrap = check_resamples(bootstrap)
    if not results:
        raise ScoringInputError("no episodes to score (the input is empty)", [])
    orphans: list[str] = []
    if retention:
        _check_clean_twins(results)
    elif retention is None:
        orphans = missing_clean_twins(results)
        retention = not orphans
    rows, matrix = outcome_matrix(results)
    point = measures(matrix)
    values = dict(zip(MEASURES, point.tolist(), strict=True))
    success = {k.removeprefix("sr/"): v for k, v in values.items() if k.startswith("sr/")}
    kept = {k: v for k, v in values.items() if retention or not k.startswith("retention/")}
    intervals: dict[str, tuple[float, float]] = {}
    if bootstrap > 0:
        low, high = bootstrap_ci(matrix, measures, resamples=bootstrap, seed=seed)
        intervals = {k: (float(lo), float(hi)) for k, lo, hi in zip(MEASURES, low, high, strict=True) if k in kept}
    changes, tests = {}, {}
    for pattern in PATTERN_CONFIGS:
        changes[pattern] = success[pattern] - success[CLEAN]
        tests[pattern] = _sr_change_test(matrix, pattern)
    per_task: dict[str, dict[str, float]] = {}
    pooled = len({r.run for r in results}) > 1  # keys: task ids for one run, `run:task` when pooled
    if retention:
        for name, only in (("all", None), *((p, p) for p in PATTERN_CONFIGS)):
            found = task_retention(rows, matrix, only)
            per_task[name] = {f"{run}:{task}" if pooled else task: v for (run, task), v in found.items()}
    return Scores(
        n_episodes=len(results),
        n_tasks=len({r.task_id for r in results}),
        success_rate=success,
        sr_change=changes,
        sr_change_test=tests,
        retention={k.removeprefix("retention/"): v for k, v in kept.items() if k.startswith("retention/")}
        if retention
        else None,
        clean_successes=int(np.nansum(matrix[:, 0] == 1)),
        task_retention=per_task,
        hazards=introduced_hazards(results),
        plan_length=plan_length_pairs(results),
        errors=error_cases(results) if classify_errors else (),
        intervals=intervals,
        episodes=tuple(results),
        without_clean_twin=tuple(orphans),
    )


def _sr_change_test(matrix: np.ndarray[Any, np.dtype[np.float64]], pattern: str) -> TestResult:
    columns = [i for i, c in enumerate(CONDITIONS) if c.pattern == pattern]
    level_means, clean = [], []
    for values in matrix:
        levels = values[columns]
        if np.isnan(values[0]) or np.all(np.isnan(levels)):
            continue
        level_means.append(float(np.nanmean(levels)))
        clean.append(float(values[0]))
    return paired_ttest(level_means, clean)


def score_plans(
    plans: Mapping[str, Sequence[str]],
    *,
    retention: bool = True,
    bootstrap: int = 1000,
    seed: int = BOOTSTRAP_SEED,
    max_steps: int = DEFAULT_MAX_STEPS,
) -> Scores:
    """Execute `plans` (instruction id -> list of skills) in the simulator and compute every measurement.

    Raises `ScoringInputError` (a ValueError naming the ids) on empty input, unknown ids, plans that are
    not lists of strings, and, when `retention` is set, pattern ids whose task has no clean plan."""
    check_resamples(bootstrap)  # before executing anything
    results = execute_plans(plans, max_steps=max_steps)
    return compute_scores(results, retention=retention, bootstrap=bootstrap, seed=seed)


def score_predictions(
    predictions: Sequence[object],
    references: Sequence[object],
    *,
    retention: bool = True,
    bootstrap: int = 1000,
    seed: int = BOOTSTRAP_SEED,
) -> Scores:
    """`score_plans` for parallel lists (plans, instruction ids), paired by id, not by position."""
    check_resamples(bootstrap)  # before executing anything
    plans = pair_predictions(predictions, references)
    results = execute_plans(plans)
    return compute_scores(results, retention=retention, bootstrap=bootstrap, seed=seed)


def score_run(run_dir: Path, *, retention: bool = True, bootstrap: int = 1000, seed: int = BOOTSTRAP_SEED) -> Scores:
    """Score a run directory from its stored outcomes (`talkdem verify-run` re-executes them)."""
    check_resamples(bootstrap)
    return compute_scores(results_from_run(run_dir), retention=retention, bootstrap=bootstrap, seed=seed)


def compare_retention(method: Scores, reference: Scores, pattern: str | None = None) -> TestResult:
    """Two-sided paired t-test of per-task retention, `method` minus `reference`, over tasks solved under
    clean by both (the paper's method-vs-CARE tests); `pattern` restricts to that pattern's three levels."""
    key = pattern or "all"
    if not method.task_retention or not reference.task_retention:
        raise ValueError("both scores need retention (computed with retention=True)")
    a, b = method.task_retention[key], reference.task_retention[key]
    common = sorted(set(a) & set(b))
    return paired_ttest([a[t] for t in common], [b[t] for t in common])
