"""Where a run directory keeps its episodes: `episodes.jsonl`, or `episodes.jsonl.gz` once packed.

A packed file is the gzip of exactly the bytes of `episodes.jsonl` (committed runs are packed: traces
compress about tenfold). The gzip header carries no time and no file name, so packing the same episodes
twice gives the same bytes and a re-packed run shows no change in git. A folder holding both files is
refused: which one is current cannot be told from the files.
"""

from __future__ import annotations

import gzip
import io
import os
import zlib
from pathlib import Path

__all__ = [
    "EPISODES_FILE",
    "PACKED_EPISODES_FILE",
    "BothEpisodeFilesError",
    "episodes_file",
    "pack_bytes",
    "read_episode_bytes",
    "replace_file",
    "unpack_in_place",
]

EPISODES_FILE = "episodes.jsonl"
PACKED_EPISODES_FILE = "episodes.jsonl.gz"


class BothEpisodeFilesError(ValueError):
    """A run directory holds its episodes both plain and packed."""


def episodes_file(run_dir: Path) -> Path | None:
    """The file holding the run's episodes (plain or packed), None when there is neither."""
    plain, packed = run_dir / EPISODES_FILE, run_dir / PACKED_EPISODES_FILE
    if plain.is_file() and packed.is_file():
        raise BothEpisodeFilesError(
            f"{run_dir}: holds both {EPISODES_FILE} and {PACKED_EPISODES_FILE}; keep only the current one "
            f"(when both hold the same episodes, an interrupted `talkdem pack` left them: run it again, or "
            f"`talkdem pack --unpack`, to finish)"
        )
    if packed.is_file():
        return packed
    return plain if plain.is_file() else None


def read_episode_bytes(path: Path) -> bytes:
    """The bytes of `episodes.jsonl`, read from it or from its packed copy."""
    data = path.read_bytes()
    if path.name != PACKED_EPISODES_FILE:
        return data
    try:
        return gzip.decompress(data)
    except (OSError, EOFError, zlib.error) as exc:  # BadGzipFile is an OSError; a cut file raises EOFError
        raise ValueError(f"{path}: not a readable gzip file ({exc})") from None


def pack_bytes(data: bytes) -> bytes:
    """`data` gzipped deterministically: no modification time, no file name, the best compression."""
    buffer = io.BytesIO()
    with gzip.GzipFile(filename="", mode="wb", compresslevel=9, fileobj=buffer, mtime=0) as handle:
        handle.write(data)
    return buffer.getvalue()


def replace_file(path: Path, data: bytes) -> None:
    """Write `path` atomically and durably (a crash leaves the old file or the new one, never half)."""
    scratch = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    with scratch.open("wb") as handle:
        handle.write(data)
        handle.flush()
        os.fsync(handle.fileno())
    os.replace(scratch, path)


def unpack_in_place(run_dir: Path) -> bool:
    """Turn a packed run back into `episodes.jsonl` (written first, then the packed copy removed, so a crash
    between the two loses nothing); False when the run was not packed. The caller holds the run lock."""
    path = episodes_file(run_dir)
    if path is None or path.name != PACKED_EPISODES_FILE:
        return False
    replace_file(run_dir / EPISODES_FILE, read_episode_bytes(path))
    path.unlink()
    return True
