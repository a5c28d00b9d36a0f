"""Writing a file whole or not at all, and locking a file or folder: the one way every writer does both.

A file is written to a scratch name beside it (`.<name>.<pid>.tmp`: hidden, and no reader's pattern such as
`*.npz` or `*.parquet` matches it), fsynced, then renamed over the target, so a crash or a kill leaves the old
file or the new one, never half of one, and a reader never sees a file being written. A lock is POSIX `flock`
on the path itself: it ends with the process, so a killed holder never leaves a stale lock behind.

Only the standard library: the runs, the builders, the model catalog and the caches all import this module,
so it imports nothing of the project.
"""

from __future__ import annotations

import fcntl
import os
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

__all__ = ["exclusive_lock", "replace_file", "replacing"]


@contextmanager
def replacing(path: Path) -> Iterator[Path]:
    """A scratch path to write `path`'s new content to; when the block ends without an error the scratch file
    is fsynced and renamed over `path` (atomic), and on an error it is removed and `path` is left as it was.
    For writers that need a file name (pyarrow, numpy); `replace_file` writes bytes or text."""
    scratch = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        yield scratch
        descriptor = os.open(scratch, os.O_RDONLY)
        try:
            os.fsync(descriptor)
        finally:
            os.close(descriptor)
        os.replace(scratch, path)
    finally:
        scratch.unlink(missing_ok=True)


def replace_file(path: Path, data: bytes | str) -> None:
    """Write `path` atomically and durably (a crash leaves the old file or the new one, never half); text is
    written as UTF-8."""
    with replacing(path) as scratch:
        scratch.write_bytes(data.encode("utf-8") if isinstance(data, str) else data)


@contextmanager
def exclusive_lock(path: Path, in_use: Exception | None = None) -> Iterator[None]:
    """Hold an exclusive lock on `path` (a folder, or a file created empty if it is missing; its content is never
    touched) while the block runs. With `in_use`, a lock another process holds raises `in_use` at once; without,
    the lock is waited for."""
    # A folder can only be opened for reading; a file is opened for writing so that a missing one is created.
    flags = os.O_RDONLY if path.is_dir() else os.O_WRONLY | os.O_CREAT
    descriptor = os.open(path, flags, 0o666)
    try:
        try:
            fcntl.flock(descriptor, fcntl.LOCK_EX | (fcntl.LOCK_NB if in_use is not None else 0))
        except BlockingIOError:
            assert in_use is not None  # only a non-blocking lock is refused
            raise in_use from None
        yield
    finally:
        os.close(descriptor)  # closing the only descriptor releases the lock
