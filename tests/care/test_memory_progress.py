"""The first CARE run embeds the whole memory bank (~40 s on 2 cores): it says so, with the count and the
rate, and a run that finds the bank cached says nothing. The encoder here is a stand-in (the progress is
what is tested, around it); the vectors it returns are what `memory_embeddings` must return and cache."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pytest
from numpy.typing import NDArray

from care.embedding_cache import CachedEncoder
from care.memory import memory_embeddings
from talkdem.instructions import load_memory_bank


def _encode(texts: Sequence[str]) -> NDArray[np.float64]:
    rows = np.array([[len(t), t.count(" ") + 1.0, 1.0] for t in texts], dtype=np.float64)
    normalized: NDArray[np.float64] = rows / np.linalg.norm(rows, axis=1, keepdims=True)
    return normalized


def test_the_first_embedding_shows_count_and_rate(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    memory = load_memory_bank()[:25]
    first = memory_embeddings(memory, CachedEncoder(_encode, "stand-in", tmp_path), "stand-in")
    err = capsys.readouterr().err
    assert "CARE: embedding the memory bank (25 instructions, stand-in); once per machine, then cached" in err
    assert "CARE: memory bank embedded: 25 instructions in" in err and "per s)" in err
    # Another process: only the disk is shared, and the bank comes from the embedding cache.
    again = CachedEncoder(_encode, "stand-in", tmp_path)
    assert np.array_equal(memory_embeddings(memory, again, "stand-in"), first) and again.encoded == 0
    assert capsys.readouterr().err == ""  # cached: nothing to report
    assert np.array_equal(first, _encode([m.instruction for m in memory]))


def test_a_partly_cached_bank_says_how_much_is_left(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    memory = load_memory_bank()[:6]
    CachedEncoder(_encode, "stand-in", tmp_path)([m.instruction for m in memory[:4]])
    encoder = CachedEncoder(_encode, "stand-in", tmp_path)
    vectors = memory_embeddings(memory, encoder, "stand-in")
    assert "CARE: embedding the memory bank (2 of 6 instructions, stand-in)" in capsys.readouterr().err
    assert encoder.encoded == 2 and np.array_equal(vectors, _encode([m.instruction for m in memory]))


def test_an_encoder_without_a_cache_is_not_said_to_cache(capsys: pytest.CaptureFixture[str]) -> None:
    memory = load_memory_bank()[:3]
    assert memory_embeddings(memory, _encode, "stand-in").shape == (3, 3)
    err = capsys.readouterr().err
    assert "CARE: embedding the memory bank (3 instructions, stand-in)\n" in err and "cached" not in err
