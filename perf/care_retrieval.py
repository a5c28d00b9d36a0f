"""CARE's retrieval for the whole benchmark, side by side with the encoder's own time.

- encoder alone: all-MiniLM-L6-v2 through sentence-transformers (batch 64), the 1,600 memory-bank items and
  the 4,800 instructions, nothing else;
- CARE cold: a new CARE strategy with an empty embedding cache embeds the memory bank and retrieves the top 3
  items for every instruction (what a first `talkdem run --strategy care` over all episodes does);
- CARE repeated: the same in a new strategy object (as a new process would), with the cache on disk.
The encoder is loaded before any timing (the load is printed apart).
"""

from __future__ import annotations

import os
import tempfile
import time
from pathlib import Path

COLD_GOAL = 1.2
"""A cold run within this factor of the encoder's own time."""
WARM_GOAL_SECONDS = 2.0


def main() -> None:
    os.environ.setdefault("HF_HUB_OFFLINE", "1")
    os.environ.setdefault("TOKENIZERS_PARALLELISM", "false")
    from care.strategy import ContextAwareRetrieval
    from talkdem.embeddings import load_encoder
    from talkdem.instructions import load_instructions, load_memory_bank
    from talkdem.paths import CACHE_DIR_ENV

    memory = load_memory_bank()
    texts = [instruction.text for instruction in load_instructions()]
    start = time.perf_counter()
    encoder = load_encoder()
    load = time.perf_counter() - start
    load_before = os.getloadavg()[0]

    start = time.perf_counter()
    encoder.encode([item.instruction for item in memory], batch_size=64, show_progress_bar=False)
    own_memory = time.perf_counter() - start
    start = time.perf_counter()
    encoder.encode(texts, batch_size=64, show_progress_bar=False)
    own_queries = time.perf_counter() - start
    own = own_memory + own_queries

    previous = os.environ.get(CACHE_DIR_ENV)
    with tempfile.TemporaryDirectory() as folder:
        os.environ[CACHE_DIR_ENV] = str(Path(folder))
        try:
            timings = []
            for _ in range(2):
                start = time.perf_counter()
                care = ContextAwareRetrieval(memory)
                retrieved = care.retrieve(texts)
                timings.append(time.perf_counter() - start)
                assert len(retrieved) == len(texts)
        finally:
            if previous is None:
                del os.environ[CACHE_DIR_ENV]
            else:
                os.environ[CACHE_DIR_ENV] = previous
    cold, warm = timings
    print(
        f"care: {len(memory)} memory items + {len(texts)} instructions, top-3 each; encoder load {load:.1f} s "
        f"(not counted); load average {load_before:.1f} -> {os.getloadavg()[0]:.1f} on {os.cpu_count()} CPUs"
    )
    print(f"  encoder alone      {own:6.1f} s  (memory {own_memory:.1f} s, instructions {own_queries:.1f} s)")
    print(
        f"  CARE cold          {cold:6.1f} s  x{cold / own:.2f} of the encoder alone "
        f"(goal <= x{COLD_GOAL}: {'met' if cold <= COLD_GOAL * own else 'NOT met'})"
    )
    print(
        f"  CARE repeated      {warm:6.2f} s  embeddings cached by (text, encoder) "
        f"(goal < {WARM_GOAL_SECONDS} s: {'met' if warm < WARM_GOAL_SECONDS else 'NOT met'})"
    )


if __name__ == "__main__":
    main()
