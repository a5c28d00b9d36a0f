"""The build checkpoint's lock and its one way of appending a record, shared by `talkdem build`
(`builders.build`) and the LLM sample (`builders.reporting.llm_sample`), which resume from the same format.

The lock is the project's one file lock (`talkdem.files.exclusive_lock`, which also locks a run's folder);
a checkpoint is one JSONL file locked by itself.
"""

from __future__ import annotations

import json
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from talkdem.files import exclusive_lock

__all__ = ["CheckpointInUseError", "append_record", "checkpoint_lock"]


class CheckpointInUseError(ValueError):
    """Another build is appending to the checkpoint."""


@contextmanager
def checkpoint_lock(path: Path) -> Iterator[None]:
    """Hold an exclusive lock on the checkpoint `path` (created empty if missing); a second holder fails at once
    with `CheckpointInUseError`."""
    # A lock on the checkpoint itself: two builds appending to one checkpoint would interleave units.
    path.parent.mkdir(parents=True, exist_ok=True)
    busy = CheckpointInUseError(f"{path}: another build is using this checkpoint; wait for it")
    with exclusive_lock(path, in_use=busy):
        yield


def append_record(path: Path, record: dict[str, Any]) -> None:
    """Append `record` to the checkpoint as one JSON line, flushed."""
    with path.open("a", encoding="utf-8") as handle:
        handle.write(json.dumps(record, ensure_ascii=False) + "\n")
        handle.flush()  # a killed process loses nothing flushed; a torn last line is repaired on resume
