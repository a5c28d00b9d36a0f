"""Success rate and clean-conditioned retention from a task x condition outcome matrix.

Rows are tasks (within a run), columns the 16 conditions (`CONDITIONS`): 1 success, 0 failure, NaN not
evaluated. One vectorised function (`measures`) computes every rate, for the point estimates and for
each bootstrap resample alike, so intervals and estimates can never disagree on a definition.

- SR of a condition: successes / episodes evaluated under it.
- SR of a pattern: the mean of its level SRs; the average SR: the mean over the 15 pattern conditions.
- Retention of a pattern x level (the paper's |S_clean ∩ S_p,l| / |S_clean|): among tasks solved under
  clean *and evaluated under p,l*, the share also solved under p,l. With every task evaluated under
  every condition this is exactly the paper's formula; on a sample it keeps the denominator honest.
- Retention of a pattern: the mean over its levels; the average retention: the mean over the 15.
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from talkdem.metrics.episodes import EpisodeResult
from talkdem.schema import CONDITIONS, LEVELS, PATTERN_CONFIGS, Condition

__all__ = [
    "MEASURES",
    "condition_key",
    "measures",
    "outcome_matrix",
    "task_retention",
]

_PATTERN_COLUMNS = {p: [1 + i * len(LEVELS) + j for j in range(len(LEVELS))] for i, p in enumerate(PATTERN_CONFIGS)}


def condition_key(condition: Condition) -> str:
    """`clean` or `<pattern>:<level>` (the keys of every per-condition result)."""
    return str(condition)


MEASURES: tuple[str, ...] = (
    *(f"sr/{condition_key(c)}" for c in CONDITIONS),
    *(f"sr/{p}" for p in PATTERN_CONFIGS),
    "sr/average",
    *(f"retention/{condition_key(c)}" for c in CONDITIONS[1:]),
    *(f"retention/{p}" for p in PATTERN_CONFIGS),
    "retention/average",
)
"""The names of `measures`' output columns, in order."""


def outcome_matrix(results: Sequence[EpisodeResult]) -> tuple[list[tuple[str, str]], NDArray[np.float64]]:
    """(run, task) row labels and the rows x 16 outcome matrix (1, 0, NaN)."""
    column = {c: i for i, c in enumerate(CONDITIONS)}
    rows = sorted({(r.run, r.task_id) for r in results})
    row = {key: i for i, key in enumerate(rows)}
    matrix = np.full((len(rows), len(CONDITIONS)), np.nan)
    for result in results:
        matrix[row[(result.run, result.task_id)], column[result.condition]] = float(result.success)
    return rows, matrix


def _nanmean(values: NDArray[np.float64], axis: int) -> NDArray[np.float64]:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # an all-NaN slice is an undefined rate: NaN
        out: NDArray[np.float64] = np.nanmean(values, axis=axis)
    return out


def measures(matrix: NDArray[np.float64]) -> NDArray[np.float64]:
    """Every rate of `MEASURES` for an outcome matrix (..., tasks, 16) -> (..., len(MEASURES))."""
    sr = _nanmean(matrix, axis=-2)  # (..., 16)
    pattern_sr = np.stack([_nanmean(sr[..., cols], axis=-1) for cols in _PATTERN_COLUMNS.values()], axis=-1)
    average_sr = _nanmean(sr[..., 1:], axis=-1)[..., None]
    clean_solved = matrix[..., :, :1] == 1
    evaluated = ~np.isnan(matrix[..., :, 1:])
    solved = matrix[..., :, 1:] == 1
    with np.errstate(invalid="ignore", divide="ignore"):
        retention = (clean_solved & solved).sum(axis=-2) / (clean_solved & evaluated).sum(axis=-2)
    retention = np.where(np.isfinite(retention), retention, np.nan)
    pattern_retention = np.stack(
        [_nanmean(retention[..., [c - 1 for c in cols]], axis=-1) for cols in _PATTERN_COLUMNS.values()], axis=-1
    )
    average_retention = _nanmean(retention, axis=-1)[..., None]
    return np.concatenate([sr, pattern_sr, average_sr, retention, pattern_retention, average_retention], axis=-1)


def task_retention(
    rows: Sequence[tuple[str, str]], matrix: NDArray[np.float64], pattern: str | None = None
) -> dict[tuple[str, str], float]:
    """Per-task retention: for each task solved under clean, the share of its evaluated pattern conditions
    (all 15, or the 3 levels of `pattern`) it also solved. The unit of the paper's method-vs-method tests."""
    columns = _PATTERN_COLUMNS[pattern] if pattern else list(range(1, len(CONDITIONS)))
    out: dict[tuple[str, str], float] = {}
    for key, values in zip(rows, matrix, strict=True):
        if values[0] != 1:
            continue
        chosen = values[columns]
        chosen = chosen[~np.isnan(chosen)]
        if chosen.size:
            out[key] = float(chosen.mean())
    return out
