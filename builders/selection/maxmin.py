"""Greedy max-min (farthest-point) sampling over a cosine-similarity matrix, and diversity statistics."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

__all__ = ["SIMILARITY_DECIMALS", "greedy_max_min", "mean_pairwise_similarity", "random_subset_similarity"]

# Similarities are rounded before every comparison so that the last bits of a float, which differ between
# BLAS builds, cannot change which candidate wins; exact ties then go to the lowest index.
SIMILARITY_DECIMALS = 6


def greedy_max_min(similarity: NDArray[np.float64], k: int) -> list[int]:
    """Indices of `k` items chosen by farthest-point sampling (paper, appendix "Diversity Sampling").

    Start from the item with the highest mean similarity to the others; then repeatedly add the item whose
    maximum similarity to the selected set is smallest.
    """
    n = similarity.shape[0]
    if similarity.shape != (n, n):
        raise ValueError(f"similarity must be square, got shape {similarity.shape}")
    if not 0 < k <= n:
        raise ValueError(f"cannot select {k} of {n} candidates")
    sims = np.round(similarity, SIMILARITY_DECIMALS)
    if n == 1:
        return [0]
    mean_to_others = np.round((sims.sum(axis=1) - np.diag(sims)) / (n - 1), SIMILARITY_DECIMALS)
    first = int(np.argmax(mean_to_others))  # argmax/argmin return the first index on ties
    selected = [first]
    max_sim_to_selected = sims[first].copy()
    available = np.ones(n, dtype=bool)
    available[first] = False
    while len(selected) < k:
        scores = np.where(available, max_sim_to_selected, np.inf)
        chosen = int(np.argmin(scores))
        selected.append(chosen)
        available[chosen] = False
        max_sim_to_selected = np.maximum(max_sim_to_selected, sims[chosen])
    return selected


def mean_pairwise_similarity(similarity: NDArray[np.float64], indices: list[int] | NDArray[np.int64]) -> float:
    """Mean cosine similarity over distinct pairs of the given items."""
    idx = np.asarray(indices)
    if idx.size < 2:
        raise ValueError("need at least two items for a pairwise similarity")
    block = similarity[np.ix_(idx, idx)]
    m = idx.size
    return float((block.sum() - np.trace(block)) / (m * (m - 1)))


def random_subset_similarity(similarity: NDArray[np.float64], k: int, draws: int, seed: int) -> tuple[float, float]:
    """Mean and standard deviation, over `draws` random `k`-subsets, of their mean pairwise similarity."""
    rng = np.random.default_rng(seed)
    n = similarity.shape[0]
    values = [mean_pairwise_similarity(similarity, rng.choice(n, size=k, replace=False)) for _ in range(draws)]
    return float(np.mean(values)), float(np.std(values))
