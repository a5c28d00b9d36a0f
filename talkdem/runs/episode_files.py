"""Where a run directory keeps its episodes: `episodes.jsonl`, or `episodes.jsonl.gz` once packed.

A packed file is the gzip of exactly the bytes of `episodes.jsonl` (committed runs are packed: traces
compress about tenfold). The gzip header carries no time and no file name, so packing the same episodes
twice gives the same bytes and a re-packed run shows no change in git. A folder holding both files is
refused: which one is current cannot be told from the files.

Every reader of an episodes file goes through `episode_lines` (or `read_episode_bytes`, built on it), which
reads in chunks and refuses, with one error naming the file, more than `MAX_EPISODES_BYTES` of episodes, more
than `MAX_LINES` lines or a line longer than `MAX_LINE_BYTES`: a small gzip file can unpack to gigabytes, and
reading it whole would end the command with a MemoryError. The limits are far above any real run (a full run of
the benchmark's 4,800 instructions with traces is about 65 MB, its longest line about 25 kB) and far below what
would exhaust memory.
"""

from __future__ import annotations

import gzip
import io
import zlib
from collections.abc import Iterator
from pathlib import Path

from talkdem.files import replace_file

__all__ = [
    "EPISODES_FILE",
    "MAX_EPISODES_BYTES",
    "MAX_LINES",
    "MAX_LINE_BYTES",
    "PACKED_EPISODES_FILE",
    "BothEpisodeFilesError",
    "EpisodeFileTooLargeError",
    "episode_lines",
    "episodes_file",
    "pack_bytes",
    "read_episode_bytes",
    "unpack_in_place",
]

EPISODES_FILE = "episodes.jsonl"
PACKED_EPISODES_FILE = "episodes.jsonl.gz"


MAX_EPISODES_BYTES = 512 * 1024 * 1024
"""The most bytes of episodes (unpacked) read from one episodes file: about eight full runs of the benchmark."""
MAX_LINE_BYTES = 16 * 1024 * 1024
"""The longest episode line read: some 600 times the longest a run has written."""
MAX_LINES = 1_000_000
"""The most lines read (blank ones too, so a file of nothing but newlines is refused as quickly): some 200
times the benchmark's 4,800 instructions."""
_CHUNK = 1024 * 1024


class BothEpisodeFilesError(ValueError):
    """A run directory holds its episodes both plain and packed."""


class EpisodeFileTooLargeError(ValueError):
    """An episodes file holding (or unpacking to) more than the limits allow."""


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


def _size(count: int) -> str:
    return f"{count // (1024 * 1024)} MiB"


def _chunks(path: Path) -> Iterator[bytes]:
    """The bytes of `episodes.jsonl` in chunks of at most `_CHUNK`, unpacked from `path` when it is the packed
    copy (decompressed a chunk at a time: nothing unpacks beyond what is asked for)."""
    try:
        with gzip.open(path, "rb") if path.name == PACKED_EPISODES_FILE else path.open("rb") as handle:
            while chunk := handle.read(_CHUNK):
                yield chunk
    except (EOFError, zlib.error, gzip.BadGzipFile) as exc:  # a cut file raises EOFError
        raise ValueError(f"{path}: not a readable gzip file ({exc})") from None


def episode_lines(path: Path) -> Iterator[bytes]:
    """The lines of `episodes.jsonl` (read from it or from its packed copy) without their newlines, as
    `bytes.split(b"\\n")` gives them (the last one is what follows the last newline, often empty); read a
    chunk at a time and refused past `MAX_EPISODES_BYTES` or `MAX_LINES` in all, or `MAX_LINE_BYTES` in one line."""
    total, number, pending = 0, 1, b""
    for chunk in _chunks(path):
        total += len(chunk)
        if total > MAX_EPISODES_BYTES:
            raise EpisodeFileTooLargeError(
                f"{path}: holds more than {_size(MAX_EPISODES_BYTES)} of episodes (unpacked), the most an episodes "
                "file may hold; not the episodes of a run"
            )
        pieces = (pending + chunk).split(b"\n")
        pending = pieces.pop()
        if number + len(pieces) > MAX_LINES:
            raise EpisodeFileTooLargeError(
                f"{path}: holds more than {MAX_LINES:,} lines, the most an episodes file may hold; "
                "not the episodes of a run"
            )
        for line in pieces:
            _check_line(path, number, line)
            yield line
            number += 1
        _check_line(path, number, pending)  # a line still going on (the whole file, in a bomb of one line)
    yield pending


def _check_line(path: Path, number: int, line: bytes) -> None:
    if len(line) > MAX_LINE_BYTES:
        raise EpisodeFileTooLargeError(
            f"{path}, line {number}: longer than {_size(MAX_LINE_BYTES)}, the longest episode line read; "
            "not an episode record"
        )


def read_episode_bytes(path: Path) -> bytes:
    """The bytes of `episodes.jsonl`, read from it or from its packed copy (within the limits of
    `episode_lines`)."""
    return b"\n".join(episode_lines(path))


def pack_bytes(data: bytes) -> bytes:
    """`data` gzipped deterministically: no modification time, no file name, the best compression."""
    buffer = io.BytesIO()
    with gzip.GzipFile(filename="", mode="wb", compresslevel=9, fileobj=buffer, mtime=0) as handle:
        handle.write(data)
    return buffer.getvalue()


def unpack_in_place(run_dir: Path) -> bool:
    """Turn a packed run back into `episodes.jsonl` (written first, then the packed copy removed, so a crash
    between the two loses nothing); False when the run was not packed. The caller holds the run lock."""
    path = episodes_file(run_dir)
    if path is None or path.name != PACKED_EPISODES_FILE:
        return False
    replace_file(run_dir / EPISODES_FILE, read_episode_bytes(path))
    path.unlink()
    return True
