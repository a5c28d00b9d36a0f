"""CARE's memory bank embedded with all-MiniLM-L6-v2, through the one embedding cache (`care.embedding_cache`)."""

from __future__ import annotations

import sys
import time
from collections.abc import Callable, Sequence

import numpy as np
from numpy.typing import NDArray

from care.embedding_cache import CachedEncoder
from talkdem.instructions import MemoryItem

__all__ = ["Encoder", "memory_embeddings"]

Encoder = Callable[[Sequence[str]], NDArray[np.float64]]


def memory_embeddings(memory: Sequence[MemoryItem], encode: Encoder, encoder_name: str) -> NDArray[np.float64]:
    """Unit-normalized embeddings of the memory instructions. Through a `CachedEncoder` (CARE's default encoder)
    each instruction is encoded once per machine and encoder, then read from the cache on disk."""
    texts = [item.instruction for item in memory]
    if isinstance(encode, CachedEncoder):
        pending, kept = encode.uncached(texts), "; once per machine, then cached"
    else:
        pending, kept = len(texts), ""
    if not pending:
        return np.asarray(encode(texts), dtype=np.float64)
    # The first CARE run on a machine embeds the whole bank (1,600 texts: ~40 s on 2 cores); say so, with the
    # count and the rate, instead of a silent pause (a terminal also gets the encoder's bar, `talkdem.embeddings`).
    part = "" if pending == len(texts) else f"{pending:,} of "
    print(
        f"CARE: embedding the memory bank ({part}{len(texts):,} instructions, {encoder_name}){kept}",
        file=sys.stderr,
        flush=True,
    )
    started = time.perf_counter()
    vectors = np.asarray(encode(texts), dtype=np.float64)
    seconds = max(time.perf_counter() - started, 1e-9)
    print(
        f"CARE: memory bank embedded: {pending:,} instructions in {seconds:.1f} s ({pending / seconds:,.0f} per s)",
        file=sys.stderr,
        flush=True,
    )
    return vectors
