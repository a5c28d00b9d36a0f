"""CARE's memory bank embedded with all-MiniLM-L6-v2, cached on disk keyed by the bank's content hash."""

from __future__ import annotations

import hashlib
import json
import sys
import time
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
    if path.is_file() and memory:
        cached: NDArray[np.float64] = np.load(path)
        # The file is keyed by the bank and the encoder's name; its shape is checked against one real
        # encoding too, so a file written by another encoder under that name is recomputed, not used.
        width = np.asarray(encode([memory[0].instruction])).shape[-1]
        if cached.ndim == 2 and cached.shape == (len(memory), width):
            return cached
    # The first CARE run on a machine embeds the whole bank (1,600 texts: ~40 s on 2 cores); say so, with the
    # count and the rate, instead of a silent pause (a terminal also gets the encoder's bar, `talkdem.embeddings`).
    print(
        f"CARE: embedding the memory bank ({len(memory):,} instructions, {encoder_name}); once per machine, "
        "then cached",
        file=sys.stderr,
        flush=True,
    )
    started = time.perf_counter()
    vectors = encode([item.instruction for item in memory])
    seconds = max(time.perf_counter() - started, 1e-9)
    print(
        f"CARE: memory bank embedded: {len(memory):,} instructions in {seconds:.1f} s "
        f"({len(memory) / seconds:,.0f} per s)",
        file=sys.stderr,
        flush=True,
    )
    folder.mkdir(parents=True, exist_ok=True)
    partial = path.with_name(path.stem + ".partial.npy")
    np.save(partial, vectors)
    partial.replace(path)  # atomic: a killed run never leaves a truncated cache
    return vectors
