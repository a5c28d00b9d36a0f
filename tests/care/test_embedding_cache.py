"""CARE's embedding cache: each (text, encoder) is encoded once, and a cached run returns exactly what the
encoder returned. The encoder here is a counting stand-in (this tests the cache, not MiniLM)."""

from __future__ import annotations

import hashlib
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from care.embedding_cache import CachedEncoder


class Counting:
    def __init__(self) -> None:
        self.seen: list[str] = []

    def __call__(self, texts: Sequence[str]) -> NDArray[np.float64]:
        self.seen += list(texts)
        digests = [hashlib.sha256(t.encode()).digest() for t in texts]
        rows = [np.frombuffer(d, dtype=np.uint8)[:8].astype(np.float64) for d in digests]
        matrix = np.array(rows) + 1.0
        normalized: NDArray[np.float64] = matrix / np.linalg.norm(matrix, axis=1, keepdims=True)
        return normalized


def test_each_text_is_encoded_once_and_results_are_identical(tmp_path: Path) -> None:
    encoder = Counting()
    cached = CachedEncoder(encoder, "enc-a", folder=tmp_path)
    first = cached(["a", "b", "a", "c"])
    assert encoder.seen == ["a", "b", "c"]
    np.testing.assert_array_equal(first, encoder(["a", "b", "a", "c"]))
    encoder.seen.clear()

    again = CachedEncoder(encoder, "enc-a", folder=tmp_path)  # a new process: only the disk is shared
    mixed = again(["c", "d", "a"])
    assert encoder.seen == ["d"]
    np.testing.assert_array_equal(mixed, Counting()(["c", "d", "a"]))
    assert again.encoded == 1
    shards = [p for p in tmp_path.rglob("*") if p.is_file()]
    # two shards (one per call that encoded something) and no scratch file left behind
    assert len(shards) == 2 and all(p.suffix == ".npz" and not p.name.startswith(".") for p in shards)


def test_another_encoder_name_does_not_hit(tmp_path: Path) -> None:
    encoder = Counting()
    CachedEncoder(encoder, "enc-a", folder=tmp_path)(["a", "b"])
    encoder.seen.clear()
    CachedEncoder(encoder, "enc-b", folder=tmp_path)(["a", "b"])
    assert encoder.seen == ["a", "b"]


def test_a_fully_cached_call_never_reaches_the_encoder(tmp_path: Path) -> None:
    encoder = Counting()
    CachedEncoder(encoder, "enc-a", folder=tmp_path)(["x", "y"])
    encoder.seen.clear()
    warm = CachedEncoder(encoder, "enc-a", folder=tmp_path)
    assert warm(["y", "x", "y"]).shape == (3, 8)
    assert encoder.seen == [] and warm.encoded == 0
