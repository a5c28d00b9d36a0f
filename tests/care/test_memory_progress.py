"""The first CARE run embeds the whole memory bank (~40 s on 2 cores): it says so, with the count and the
rate, and a run that finds the bank cached says nothing. The encoder here is a stand-in (the progress is
what is tested, around it); the vectors it returns are what `memory_embeddings` must return and cache."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pytest
from numpy.typing import NDArray

from care.memory import memory_embeddings
from talkdem.instructions import load_memory_bank


def _encode(texts: Sequence[str]) -> NDArray[np.float64]:
    rows = np.array([[len(t), t.count(" ") + 1.0, 1.0] for t in texts], dtype=np.float64)
    normalized: NDArray[np.float64] = rows / np.linalg.norm(rows, axis=1, keepdims=True)
    return normalized


def test_the_first_embedding_shows_count_and_rate(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    memory = load_memory_bank()[:25]
    first = memory_embeddings(memory, _encode, "stand-in", tmp_path)
    err = capsys.readouterr().err
    assert "CARE: embedding the memory bank (25 instructions, stand-in)" in err
    assert "CARE: memory bank embedded: 25 instructions in" in err and "per s)" in err
    again = memory_embeddings(memory, _encode, "stand-in", tmp_path)
    assert capsys.readouterr().err == ""  # cached: nothing to report
    assert np.array_equal(first, again) and np.array_equal(first, _encode([m.instruction for m in memory]))


def test_a_cached_bank_of_another_encoder_width_is_recomputed(tmp_path: Path) -> None:
    memory = load_memory_bank()[:6]
    memory_embeddings(memory, _encode, "stand-in", tmp_path)
    (cached,) = tmp_path.glob("memory-*.npy")
    np.save(cached, np.ones((6, 512)))  # another encoder's vectors under this name (seen in a shared cache)
    assert memory_embeddings(memory, _encode, "stand-in", tmp_path).shape == (6, 3)
