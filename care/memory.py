"""CARE's memory bank embedded with all-MiniLM-L6-v2, cached on disk keyed by the bank's content hash."""

from __future__ import annotations

import hashlib
import json
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from talkdem.instructions import MemoryItem
from talkdem.paths import cache_dir

__all__ = ["Encoder", "memory_embeddings", "memory_hash"]

Encoder = Callable[[Sequence[str]], NDArray[np.float64]]


def memory_hash(memory: Sequence[MemoryItem], encoder_name: str) -> str:
    """Changes whenever an item's instruction, order or the encoder changes."""
    digest = hashlib.sha256(encoder_name.encode())
    for item in memory:
        digest.update(json.dumps([item.id, item.instruction]).encode())
    return digest.hexdigest()


def memory_embeddings(
    memory: Sequence[MemoryItem], encode: Encoder, encoder_name: str, folder: Path | None = None
) -> NDArray[np.float64]:
    """Unit-normalized embeddings of the memory instructions, computed once per bank and encoder."""
    folder = folder or cache_dir() / "care"
    path = folder / f"memory-{memory_hash(memory, encoder_name)[:20]}.npy"
    if path.is_file():
        cached: NDArray[np.float64] = np.load(path)
        if cached.shape[0] == len(memory):
            return cached
    vectors = encode([item.instruction for item in memory])
    folder.mkdir(parents=True, exist_ok=True)
    partial = path.with_name(path.stem + ".partial.npy")
    np.save(partial, vectors)
    partial.replace(path)  # atomic: a killed run never leaves a truncated cache
    return vectors
