"""Packing a run directory: `episodes.jsonl` replaced by its deterministic gzip `episodes.jsonl.gz`, and back.

Every reader takes either form, so packing changes only the size on disk (committed runs are packed to keep
the repository small). Only complete runs are packed unless asked: a run still under way would be unpacked by
its next episode anyway. The run lock is held throughout, so a run being written is never packed under it.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from talkdem.files import replace_file
from talkdem.runs.episode_files import (
    EPISODES_FILE,
    PACKED_EPISODES_FILE,
    pack_bytes,
    read_episode_bytes,
    unpack_in_place,
)
from talkdem.runs.store import read_episodes, read_header, run_lock, run_progress

__all__ = ["PackResult", "pack_run", "unpack_run"]


@dataclass(frozen=True)
class PackResult:
    """What packing (or unpacking) one run directory did."""

    changed: bool
    """False when the run was already in the wanted form, or was left as it was (see `note`)."""
    size_before: int
    """Bytes of the episodes file before."""
    size_after: int
    """Bytes of the episodes file after."""
    note: str = ""
    """Why nothing changed, when that is not because the run was already in the wanted form."""


def _check_run_dir(run_dir: Path) -> None:
    if not run_dir.is_dir():
        raise ValueError(f"{run_dir}: not a run directory (no such folder)")
    read_header(run_dir)  # names the folder when it holds no header


def _finish_interrupted(run_dir: Path, keep: str) -> None:
    """A folder holding both forms with the same episodes is a pack or unpack killed between its two steps:
    it is finished by keeping `keep`. Different episodes in the two are refused (which is current is unknown)."""
    plain, packed = run_dir / EPISODES_FILE, run_dir / PACKED_EPISODES_FILE
    if not (plain.is_file() and packed.is_file()):
        return
    if read_episode_bytes(packed) != read_episode_bytes(plain):  # both within the limits of every reader
        raise ValueError(
            f"{run_dir}: holds both {EPISODES_FILE} and {PACKED_EPISODES_FILE} with different episodes; "
            "keep only the current one"
        )
    (packed if keep == EPISODES_FILE else plain).unlink()


def pack_run(run_dir: Path, *, partial: bool = False) -> PackResult:
    """Pack `run_dir`'s episodes (a complete run only, unless `partial`). The episodes are validated first,
    and a truncated last line is cut as a resume would cut it, so the packed file is exactly the plain one."""
    _check_run_dir(run_dir)
    plain, packed = run_dir / EPISODES_FILE, run_dir / PACKED_EPISODES_FILE
    with run_lock(run_dir):
        _finish_interrupted(run_dir, keep=PACKED_EPISODES_FILE)
        if packed.is_file():
            size = packed.stat().st_size
            return PackResult(False, size, size)
        if not plain.is_file():
            return PackResult(False, 0, 0, "holds no episodes")
        progress = run_progress(run_dir)
        if not progress.complete and not partial:
            size = plain.stat().st_size
            return PackResult(False, size, size, f"{progress}; --partial packs it anyway")
        read_episodes(run_dir, repair=True)
        data = read_episode_bytes(plain)
        replace_file(packed, pack_bytes(data))
        plain.unlink()  # after the packed copy is on disk: a crash between the two loses nothing
        return PackResult(True, len(data), packed.stat().st_size)


def unpack_run(run_dir: Path) -> PackResult:
    """Turn `run_dir`'s packed episodes back into `episodes.jsonl` (byte for byte what was packed)."""
    _check_run_dir(run_dir)
    plain, packed = run_dir / EPISODES_FILE, run_dir / PACKED_EPISODES_FILE
    with run_lock(run_dir):
        _finish_interrupted(run_dir, keep=EPISODES_FILE)
        if not packed.is_file():
            size = plain.stat().st_size if plain.is_file() else 0
            return PackResult(False, size, size)
        before = packed.stat().st_size
        unpack_in_place(run_dir)
        return PackResult(True, before, plain.stat().st_size)
