"""The paper's statistics: two-sided paired t-tests, a task-clustered t-test, bootstrap intervals, stars.

scipy is imported inside the functions that need it, so `import talkdem.metrics` stays light.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "BOOTSTRAP_SEED",
    "MIN_RESAMPLES",
    "TestResult",
    "bootstrap_ci",
    "check_resamples",
    "clustered_mean_test",
    "detectable_difference",
    "paired_ttest",
    "stars",
]

BOOTSTRAP_SEED = 20240917
"""Fixed so that the same episodes always give the same intervals."""


@dataclass(frozen=True)
class TestResult:
    """A two-sided test of a mean paired difference (`a - b`); NaN where the test is undefined."""

    mean_difference: float
    statistic: float
    p_value: float
    n: int
    """Pairs (or, for the clustered test, observations; `clusters` counts the tasks)."""
    clusters: int = 0

    def to_json(self) -> dict[str, float | int | None]:
        return {
            "mean_difference": _finite(self.mean_difference),
            "statistic": _finite(self.statistic),
            "p_value": _finite(self.p_value),
            "n": self.n,
            "clusters": self.clusters,
        }


def _finite(value: float) -> float | None:
    return None if math.isnan(value) else value


def paired_ttest(a: Sequence[float], b: Sequence[float]) -> TestResult:
    """Two-sided paired t-test of `a` against `b` (scipy's `ttest_rel`).

    Fewer than two pairs, or differences that are all equal (zero variance), leave the test undefined:
    statistic and p-value are NaN, never a spurious p of 0 or 1."""
    if len(a) != len(b):
        raise ValueError(f"paired samples differ in length ({len(a)} and {len(b)})")
    x, y = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    n = len(x)
    mean = float(np.mean(x - y)) if n else math.nan
    if n < 2 or np.ptp(x - y) == 0:
        return TestResult(mean, math.nan, math.nan, n)
    from scipy import stats

    result = stats.ttest_rel(x, y)
    return TestResult(mean, float(result.statistic), float(result.pvalue), n)


def clustered_mean_test(differences: Sequence[float], clusters: Sequence[str]) -> TestResult:
    """Two-sided t-test that the mean of `differences` is 0, with standard errors clustered by `clusters`.

    The intercept-only regression with CR1 cluster-robust variance:
    SE^2 = G/(G-1) * sum_g (sum_{i in g} (d_i - mean))^2 / N^2, t = mean/SE on G-1 degrees of freedom.
    With one observation per cluster this is exactly the paired t-test."""
    if len(differences) != len(clusters):
        raise ValueError("differences and clusters differ in length")
    d = np.asarray(differences, dtype=float)
    n = len(d)
    labels = sorted(set(clusters))
    g = len(labels)
    mean = float(d.mean()) if n else math.nan
    if g < 2:
        return TestResult(mean, math.nan, math.nan, n, g)
    position = {label: i for i, label in enumerate(labels)}
    sums = np.zeros(g)
    np.add.at(sums, [position[c] for c in clusters], d - mean)
    variance = g / (g - 1) * float(np.sum(sums**2)) / n**2
    if variance <= 0:
        return TestResult(mean, math.nan, math.nan, n, g)
    from scipy import stats

    statistic = mean / math.sqrt(variance)
    p_value = float(2 * stats.t.sf(abs(statistic), g - 1))
    return TestResult(mean, statistic, p_value, n, g)


def detectable_difference(test: TestResult, *, power: float = 0.8, alpha: float = 0.05) -> float:
    """The smallest true mean difference this test would find significant (two-sided `alpha`) with
    probability `power`, at its own sample size and observed spread: (t_{1-alpha/2} + t_{power}) x SE on its
    degrees of freedom. It says what a run can and cannot tell: a difference below it may well be real and
    still read as no difference. The standard error comes back out of the test (|mean / t|), so it is NaN
    where the test is undefined or the observed mean difference is exactly 0."""
    dof = (test.clusters or test.n) - 1
    if dof < 1 or math.isnan(test.statistic) or test.statistic == 0:
        return math.nan
    from scipy import stats

    standard_error = abs(test.mean_difference / test.statistic)
    return float((stats.t.ppf(1 - alpha / 2, dof) + stats.t.ppf(power, dof)) * standard_error)


MIN_RESAMPLES = 40
"""The fewest resamples a 95% percentile interval is made from: each 2.5% tail then holds at least one
resample (40 x 2.5% = 1). With fewer, `nanpercentile` interpolates between the two most extreme resamples
and the "interval" is an artefact of the count, which would be published as a 95% interval."""


def check_resamples(value: object, name: str = "bootstrap") -> int:
    """`value` as a bootstrap resample count: 0 (no intervals, the documented off switch) or a whole number
    of at least `MIN_RESAMPLES`; a `ValueError` naming `name` otherwise (a bool, 2.5 or -5 included)."""
    import numbers

    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise ValueError(
            f"{name} must be a whole number of resamples (0: no intervals, or at least {MIN_RESAMPLES}), "
            f"got {value!r} ({type(value).__name__})"
        )
    count = int(value)
    if count != 0 and count < MIN_RESAMPLES:
        raise ValueError(
            f"{name} must be 0 (no intervals) or at least {MIN_RESAMPLES} resamples (a 95% interval needs one "
            f"resample in each 2.5% tail), got {count}"
        )
    return count


def bootstrap_ci(
    rows: NDArray[np.float64],
    statistic: Callable[[NDArray[np.float64]], NDArray[np.float64]],
    *,
    resamples: int = 1000,
    level: float = 0.95,
    seed: int = BOOTSTRAP_SEED,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Percentile bootstrap over rows (tasks): resample rows with replacement `resamples` times.

    `statistic` maps an array of shape (B, n, ...) to (B, k) (one value per resample and quantity);
    returns (low, high), each of shape (k,). NaN quantities (undefined in a resample) are ignored."""
    if check_resamples(resamples, "resamples") == 0:
        raise ValueError(f"resamples must be at least {MIN_RESAMPLES} for an interval, got 0")
    n = rows.shape[0]
    rng = np.random.default_rng(seed)
    values = np.empty((0,))
    chunks = []
    for start in range(0, resamples, 250):  # bounded memory for large runs
        size = min(250, resamples - start)
        chunks.append(statistic(rows[rng.integers(0, n, size=(size, n))]))
    values = np.concatenate(chunks, axis=0)
    tail = (1 - level) / 2 * 100
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN columns give NaN bounds
        low = np.nanpercentile(values, tail, axis=0)
        high = np.nanpercentile(values, 100 - tail, axis=0)
    return low, high


def stars(p_value: float | None) -> str:
    """`***` p<0.001, `**` p<0.01, `*` p<0.05, else empty (NaN / None: empty)."""
    if p_value is None or math.isnan(p_value):
        return ""
    if p_value < 0.001:
        return "***"
    if p_value < 0.01:
        return "**"
    if p_value < 0.05:
        return "*"
    return ""
