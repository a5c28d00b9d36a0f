"""Top-k cosine retrieval over the memory bank."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

__all__ = ["top_k"]


def top_k(queries: NDArray[np.float64], memory: NDArray[np.float64], k: int) -> list[list[int]]:
    """For each (unit-normalized) query row, the indices of the `k` most similar memory rows, best first.

    Ties keep the lower index first (stable sort on negated similarity), so retrieval is deterministic.
    """
    if k <= 0 or k > memory.shape[0]:
        raise ValueError(f"k must be in 1..{memory.shape[0]}, got {k}")
    similarity = np.round(queries @ memory.T, 6)
    order = np.argsort(-similarity, axis=1, kind="stable")[:, :k]
    return [[int(i) for i in row] for row in order]
