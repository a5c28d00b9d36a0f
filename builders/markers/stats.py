"""Group statistics of the paper: Mann-Whitney U, Cohen's d, and the Wasserstein-1 delta of Level 3."""

from __future__ import annotations

import math
from collections.abc import Sequence

__all__ = ["cohens_d", "delta_w_l3", "mann_whitney"]


def cohens_d(dementia: Sequence[float], control: Sequence[float]) -> float:
    """(mean_dem - mean_ctrl) / pooled standard deviation; positive when dementia is higher."""
    n1, n2 = len(dementia), len(control)
    if n1 < 2 or n2 < 2:
        raise ValueError("Cohen's d needs at least two values per group")
    m1, m2 = sum(dementia) / n1, sum(control) / n2
    v1 = sum((x - m1) ** 2 for x in dementia) / (n1 - 1)
    v2 = sum((x - m2) ** 2 for x in control) / (n2 - 1)
    pooled = math.sqrt(((n1 - 1) * v1 + (n2 - 1) * v2) / (n1 + n2 - 2))
    return (m1 - m2) / pooled if pooled else 0.0


def mann_whitney(dementia: Sequence[float], control: Sequence[float]) -> tuple[float, float]:
    """Two-sided Mann-Whitney U test: (U statistic of the dementia group, p value)."""
    from scipy.stats import mannwhitneyu

    result = mannwhitneyu(list(dementia), list(control), alternative="two-sided")
    return float(result.statistic), float(result.pvalue)


def delta_w_l3(level3: Sequence[float], control: Sequence[float], dementia: Sequence[float]) -> float:
    """W1(L3, Ctrl) - W1(L3, Dem): positive when Level 3 is closer to dementia speech."""
    from scipy.stats import wasserstein_distance

    return float(wasserstein_distance(level3, control) - wasserstein_distance(level3, dementia))
