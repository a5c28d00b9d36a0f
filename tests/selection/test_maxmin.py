"""Greedy max-min sampling and the diversity statistics on hand-computed cases."""

from __future__ import annotations

import numpy as np
import pytest

from builders.selection import greedy_max_min, mean_pairwise_similarity, memory_quotas, random_subset_similarity


def _similarity_of(points: list[list[float]]) -> np.ndarray:
    v = np.asarray(points, dtype=np.float64)
    v /= np.linalg.norm(v, axis=1, keepdims=True)
    return v @ v.T


def test_hand_computed_order() -> None:
    sim = np.array(
        [
            [1.0, 0.9, 0.2, 0.5],
            [0.9, 1.0, 0.3, 0.6],
            [0.2, 0.3, 1.0, 0.4],
            [0.5, 0.6, 0.4, 1.0],
        ]
    )
    # Means to others: 0 -> 0.533, 1 -> 0.600, 2 -> 0.300, 3 -> 0.500: start at 1.
    # Max similarity to {1}: 0 -> 0.9, 2 -> 0.3, 3 -> 0.6: take 2. Then to {1, 2}: 0 -> 0.9, 3 -> 0.6: take 3.
    assert greedy_max_min(sim, 3) == [1, 2, 3]
    assert greedy_max_min(sim, 4) == [1, 2, 3, 0]


def test_ties_go_to_the_lowest_index() -> None:
    sim = np.full((4, 4), 0.5)
    np.fill_diagonal(sim, 1.0)
    assert greedy_max_min(sim, 4) == [0, 1, 2, 3]


def test_invalid_requests() -> None:
    with pytest.raises(ValueError, match="cannot select 5 of 4"):
        greedy_max_min(np.eye(4), 5)
    with pytest.raises(ValueError, match="square"):
        greedy_max_min(np.ones((2, 3)), 1)


def test_mean_pairwise_similarity_excludes_self_pairs() -> None:
    sim = np.array([[1.0, 0.2, 0.4], [0.2, 1.0, 0.6], [0.4, 0.6, 1.0]])
    assert mean_pairwise_similarity(sim, [0, 1, 2]) == pytest.approx(0.4)
    assert mean_pairwise_similarity(sim, [1, 2]) == pytest.approx(0.6)


def test_random_baseline_is_seeded() -> None:
    rng = np.random.default_rng(3)
    sim = _similarity_of(rng.normal(size=(30, 8)).tolist())
    assert random_subset_similarity(sim, 10, 20, seed=0) == random_subset_similarity(sim, 10, 20, seed=0)
    assert random_subset_similarity(sim, 10, 20, seed=0) != random_subset_similarity(sim, 10, 20, seed=1)


def test_memory_quotas_spread_100_over_six_types() -> None:
    quotas = memory_quotas(["f", "e", "d", "c", "b", "a"], 100)
    assert quotas == {"a": 17, "b": 17, "c": 17, "d": 17, "e": 16, "f": 16}
