"""Reading and appending run directories; a run killed mid-write resumes without losing finished episodes."""

from __future__ import annotations

import json
import os
import warnings
from pathlib import Path

from talkdem.runs.records import EpisodeRecord, RunHeader

__all__ = ["EPISODES_FILE", "HEADER_FILE", "EpisodeWriter", "read_episodes", "read_header", "write_header"]

HEADER_FILE = "header.json"
EPISODES_FILE = "episodes.jsonl"


def write_header(run_dir: Path, header: RunHeader) -> None:
    run_dir.mkdir(parents=True, exist_ok=True)
    (run_dir / HEADER_FILE).write_text(json.dumps(header.to_json(), indent=2) + "\n")


def read_header(run_dir: Path) -> RunHeader:
    path = run_dir / HEADER_FILE
    if not path.is_file():
        raise FileNotFoundError(f"{path}: not a run directory (no {HEADER_FILE})")
    try:
        return RunHeader.from_json(json.loads(path.read_text()))
    except (json.JSONDecodeError, ValueError) as exc:
        raise ValueError(f"{path}: {exc}") from exc


def read_episodes(run_dir: Path, *, repair: bool = False) -> list[EpisodeRecord]:
    """Episodes in file order. A truncated last line (a run killed while writing) is dropped with a
    warning, and cut from the file when `repair` is set; a bad line elsewhere is an error naming it."""
    path = run_dir / EPISODES_FILE
    if not path.is_file():
        return []
    raw = path.read_bytes()
    lines = raw.split(b"\n")
    episodes: list[EpisodeRecord] = []
    good_bytes = 0
    for number, line in enumerate(lines, start=1):
        if not line.strip():
            good_bytes += len(line) + 1
            continue
        try:
            episodes.append(EpisodeRecord.from_json(json.loads(line)))
        except (json.JSONDecodeError, KeyError, TypeError, ValueError) as exc:
            is_last = all(not rest.strip() for rest in lines[number:])
            if not is_last:
                raise ValueError(f"{path}, line {number}: not an episode record ({exc})") from exc
            warnings.warn(
                f"{path}, line {number}: truncated last record dropped (the run was interrupted)", stacklevel=2
            )
            if repair:
                with path.open("r+b") as handle:
                    handle.truncate(good_bytes)
            break
        good_bytes += len(line) + 1
    return episodes


class EpisodeWriter:
    """Appends one JSON line per finished episode and flushes it to disk at once."""

    def __init__(self, run_dir: Path) -> None:
        self.path = run_dir / EPISODES_FILE
        run_dir.mkdir(parents=True, exist_ok=True)
        self._handle = self.path.open("a", encoding="utf-8")

    def write(self, episode: EpisodeRecord) -> None:
        self._handle.write(episode.to_line() + "\n")
        self._handle.flush()
        os.fsync(self._handle.fileno())

    def close(self) -> None:
        self._handle.close()

    def __enter__(self) -> EpisodeWriter:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
