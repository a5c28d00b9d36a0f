"""Reading and appending run directories, safely: one writer at a time, nothing lost, nothing mixed.

    RUN_DIR/header.json      what the run is (model, planner, strategy, settings); written first
    RUN_DIR/episodes.jsonl   one finished episode per line, flushed and fsynced as it finishes
                             (or episodes.jsonl.gz, its gzip: a packed run, read the same way)

A run killed mid-write resumes without losing finished episodes: a truncated last line is cut before
anything is appended, so a new record is never glued onto half of an old one. Two processes on one run
directory would both append every episode; the second is refused while the first holds the lock. A run
resumed with settings that change results (another model, step limit, scoring, ...) is refused, since
its episodes could not be pooled; so is a folder of episodes without the header that says whose they are.
A packed run is unpacked by the first episode appended to it, never before (a complete run stays packed).
"""

from __future__ import annotations

import json
import os
import sys
import warnings
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path
from typing import TextIO

from talkdem.files import exclusive_lock, replace_file
from talkdem.runs.episode_files import (
    EPISODES_FILE,
    PACKED_EPISODES_FILE,
    episode_lines,
    episodes_file,
    unpack_in_place,
)
from talkdem.runs.records import EpisodeRecord, RunHeader
from talkdem.serialization import parse_json

__all__ = [
    "EPISODES_FILE",
    "HEADER_FILE",
    "PACKED_EPISODES_FILE",
    "EpisodeWriter",
    "RunInUseError",
    "RunProgress",
    "finish_status",
    "open_run",
    "read_episodes",
    "read_header",
    "run_lock",
    "run_progress",
    "set_status",
    "write_header",
]

HEADER_FILE = "header.json"


class RunInUseError(ValueError):
    """Another process is writing the run directory."""


def write_header(run_dir: Path, header: RunHeader) -> None:
    """Write `header.json` atomically (a crash leaves the old header or the new one, never half)."""
    run_dir.mkdir(parents=True, exist_ok=True)
    replace_file(run_dir / HEADER_FILE, json.dumps(header.to_json(), indent=2, ensure_ascii=False) + "\n")


def read_header(run_dir: Path) -> RunHeader:
    path = run_dir / HEADER_FILE
    if not path.is_file():
        raise FileNotFoundError(f"{run_dir}: not a run directory (no {HEADER_FILE} file)")
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise ValueError(f"{path}: cannot read the run header ({exc})") from None
    return RunHeader.from_json(parse_json(text, str(path)), str(path))


def read_episodes(run_dir: Path, *, repair: bool = False) -> list[EpisodeRecord]:
    """Episodes in file order, each validated, from `episodes.jsonl` or its packed copy. A truncated last
    line (a run killed while writing) is dropped with a warning, and cut from the file when `repair` is set
    (a packed file is left as it is: appending unpacks it, and the cut is made then); a bad line elsewhere,
    or an episode id stored twice, is an error naming the line."""
    path = episodes_file(run_dir)
    if path is None:
        return []
    repair = repair and path.name == EPISODES_FILE
    episodes: list[EpisodeRecord] = []
    first_line: dict[str, int] = {}
    good_bytes = 0
    unreadable: int | None = None  # the number of a line that is not JSON: an error unless nothing follows it
    # Lines are read as they come (`episode_lines` bounds the file and each line): never the whole file at once.
    for number, line in enumerate(episode_lines(path), start=1):
        if not line.strip():
            good_bytes += (len(line) + 1) if unreadable is None else 0
            continue
        if unreadable is not None:
            raise ValueError(f"{path}, line {unreadable}: not a JSON record")
        where = f"{path}, line {number}"
        try:
            data = json.loads(line.decode("utf-8"))
        except (json.JSONDecodeError, UnicodeDecodeError):
            unreadable = number
            continue
        except RecursionError:
            raise ValueError(f"{where}: JSON nested too deeply to read") from None
        # A complete line that is not a valid record is a hand-edit: refused, never scored.
        record = EpisodeRecord.from_json(data, where)
        if record.episode_id in first_line:
            raise ValueError(
                f"{where}: episode '{record.episode_id}' is stored twice (first on line "
                f"{first_line[record.episode_id]}); two processes wrote this run"
            )
        first_line[record.episode_id] = number
        episodes.append(record)
        good_bytes += len(line) + 1
    if unreadable is not None:
        # Only the last line can be cut short by a kill: drop it, the episode runs again on resume.
        warnings.warn(
            f"{path}, line {unreadable}: truncated last record dropped (the run was interrupted)", stacklevel=2
        )
        if repair:
            with path.open("r+b") as handle:
                handle.truncate(good_bytes)
    return episodes


@contextmanager
def run_lock(run_dir: Path) -> Iterator[None]:
    """Hold an exclusive lock on the run directory (POSIX `flock` on the folder itself, so no lock file
    is left behind); a second writer fails at once with `RunInUseError`. The lock ends with the process,
    so a killed run never leaves a stale lock."""
    if run_dir.exists() and not run_dir.is_dir():
        raise ValueError(f"{run_dir}: exists and is not a folder; choose another --out")
    run_dir.mkdir(parents=True, exist_ok=True)
    busy = RunInUseError(f"{run_dir}: another talkdem process is writing this run; wait for it or choose another --out")
    with exclusive_lock(run_dir, in_use=busy):
        yield


def _revisions(run_dir: Path, existing: RunHeader, wanted: RunHeader, new_revision_ok: bool) -> tuple[str, ...]:
    """The code revisions of a resumed run: refused on another revision unless the caller allows it, then
    both are recorded (oldest first)."""
    before, now = existing.code_revision, wanted.code_revision
    if not before or before == now:
        return existing.code_revisions
    if not new_revision_ok:
        raise ValueError(
            f"{run_dir} was started on code revision {before[:12]}, this is {now[:12]}: episodes of two revisions "
            "may not be comparable; pass --continue-on-new-revision to go on (both revisions are recorded in the "
            "header), or choose another --out"
        )
    recorded = existing.config.get("code_revisions")  # where merges of older versions put them
    history = existing.code_revisions or tuple(recorded if isinstance(recorded, list) else [before])
    return history if history[-1] == now else (*history, now)


def open_run(
    run_dir: Path, header: RunHeader, must_match: Sequence[str], *, new_revision_ok: bool = False
) -> list[EpisodeRecord]:
    """Start `run_dir` with `header`, or check that the run already there is the same run (every key of
    `must_match`, top-level header fields or `config.NAME`, equal; every input file unchanged; the same
    code revision unless `new_revision_ok`) and return its finished episodes. This sitting's runtime (the
    new header's) joins the recorded ones.

    The caller holds `run_lock(run_dir)`. On resume the header keeps its creation date and input hashes
    and takes the new selection (conditions, sample size, planned episode count) and status `running`:
    extending a run to more tasks is allowed, changing what a result means is not. Nothing is ever
    deleted here but a truncated last line."""
    from talkdem.runs.runtime import add_runtime
    from talkdem.runs.spec import check_same_run

    header_path = run_dir / HEADER_FILE
    if header_path.exists():
        existing = read_header(run_dir)
        check_same_run(run_dir, existing, header, must_match)
        revisions = _revisions(run_dir, existing, header, new_revision_ok)
        done = read_episodes(run_dir, repair=True)
        write_header(
            run_dir,
            existing.with_changes(
                config={**existing.config, **header.config},
                status="running",
                code_revision=header.code_revision if revisions else existing.code_revision,
                code_revisions=revisions,
                runtimes=add_runtime(existing.runtimes, header.runtimes[0] if header.runtimes else {}),
            ),
        )
        return done
    if run_dir.is_dir() and any(run_dir.iterdir()):
        has_episodes = any((run_dir / name).exists() for name in (EPISODES_FILE, PACKED_EPISODES_FILE))
        what = "episodes without a header" if has_episodes else "other files"
        raise ValueError(
            f"{run_dir}: holds {what}, not a run directory; choose an empty or new --out (nothing there was changed)"
        )
    write_header(run_dir, header)
    return []


def set_status(run_dir: Path, status: str) -> None:
    """Record the run's status (`running`, `complete`, `incomplete`) in its header."""
    write_header(run_dir, read_header(run_dir).with_changes(status=status))


def finish_status(run_dir: Path, planned: Sequence[str]) -> str:
    """`complete` when every planned episode id is on disk, else `incomplete`; recorded and returned."""
    done = {episode.episode_id for episode in read_episodes(run_dir)}
    status = "complete" if set(planned) <= done else "incomplete"
    set_status(run_dir, status)
    return status


class RunProgress:
    """How much of a run is on disk: `done` of `planned` episodes (`planned` is None for runs written
    before the header recorded it)."""

    def __init__(self, done: int, planned: int | None) -> None:
        self.done = done
        self.planned = planned

    @property
    def complete(self) -> bool:
        return self.planned is None or self.done >= self.planned

    def __str__(self) -> str:
        if self.planned is None:
            return f"{self.done} episodes"
        state = "complete" if self.complete else "INCOMPLETE"
        return f"{self.done} of {self.planned} episodes ({state})"


def run_progress(run_dir: Path) -> RunProgress:
    planned = read_header(run_dir).config.get("planned_episodes")
    return RunProgress(len(read_episodes(run_dir)), planned if isinstance(planned, int) else None)


class EpisodeWriter:
    """Appends one JSON line per finished episode and flushes it to disk at once.

    On a packed run the file is opened at the first episode written, after unpacking (said on stderr):
    appending to a gzip would leave a second file or a recompression per episode, and a complete packed run
    resumed with nothing to do stays packed. The caller holds the run lock, as for any write."""

    def __init__(self, run_dir: Path) -> None:
        self.path = run_dir / EPISODES_FILE
        run_dir.mkdir(parents=True, exist_ok=True)
        self._handle: TextIO | None = None
        found = episodes_file(run_dir)  # refuses a folder holding both files before anything is written
        if found is None or found.name == EPISODES_FILE:
            self._open()

    def _open(self) -> TextIO:
        run_dir = self.path.parent
        if unpack_in_place(run_dir):
            print(
                f"{run_dir}: unpacked {PACKED_EPISODES_FILE} to append episodes (`talkdem pack` packs it again)",
                file=sys.stderr,
            )
        self._end_last_line()
        self._handle = self.path.open("a", encoding="utf-8")
        return self._handle

    def _end_last_line(self) -> None:
        # A complete last record written without its newline (killed between the two writes) must not
        # have the next record glued onto it; a truncated one is cut by `read_episodes(repair=True)`.
        if not self.path.is_file() or self.path.stat().st_size == 0:
            return
        with self.path.open("rb") as handle:
            handle.seek(-1, os.SEEK_END)
            ends_with_newline = handle.read(1) == b"\n"
        if not ends_with_newline:
            read_episodes(self.path.parent, repair=True)
            if self.path.stat().st_size and not self.path.read_bytes().endswith(b"\n"):
                with self.path.open("ab") as handle:
                    handle.write(b"\n")

    def write(self, episode: EpisodeRecord) -> None:
        handle = self._handle or self._open()
        handle.write(episode.to_line() + "\n")
        handle.flush()
        os.fsync(handle.fileno())

    def close(self) -> None:
        if self._handle is not None:
            self._handle.close()

    def __enter__(self) -> EpisodeWriter:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
