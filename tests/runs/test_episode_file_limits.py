"""Episodes files are read in chunks and within documented limits (`talkdem.runs.episode_files`): a small packed
file that unpacks to gigabytes, a line without end, or a file of nothing but newlines is refused with one line
naming the file, by every command that reads episodes, never a MemoryError."""

from __future__ import annotations

import gzip
import json
import shutil
from pathlib import Path

import pytest

from talkdem.cli import main
from talkdem.runs import episode_files, read_episodes
from talkdem.runs.episode_files import (
    MAX_EPISODES_BYTES,
    MAX_LINE_BYTES,
    MAX_LINES,
    EpisodeFileTooLargeError,
    episode_lines,
    read_episode_bytes,
)
from talkdem.runs.pack import unpack_run

COMMITTED = Path(__file__).resolve().parent.parent.parent / "results" / "paper" / "qwen2.5-coder-0.5b-care"


def _bomb(path: Path, line: bytes, unpacked: int) -> Path:
    """A valid gzip file unpacking to about `unpacked` bytes of `line` repeated: one compressed member of 8 MiB,
    written as many times as needed (a gzip file may hold several members, read one after the other)."""
    block = 8 * 1024 * 1024
    member = gzip.compress(line * (block // len(line)), compresslevel=9, mtime=0)
    with path.open("wb") as handle:
        for _ in range(-(-unpacked // block)):
            handle.write(member)
    return path


def _run(folder: Path) -> Path:
    folder.mkdir(parents=True)
    shutil.copy(COMMITTED / "header.json", folder / "header.json")
    return folder


def test_a_packed_file_unpacking_to_gigabytes_is_refused_by_view(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The issue's example, with the real limits: about 3 MB on disk, 2 GiB unpacked, lines of 1,000 spaces."""
    run = _run(tmp_path / "run")
    packed = _bomb(run / "episodes.jsonl.gz", b" " * 999 + b"\n", 2 * 1024**3)
    assert packed.stat().st_size < 10 * 1024 * 1024
    assert main(["view", str(run), "--out", str(tmp_path / "viewer")]) == 2
    error = capsys.readouterr().err.strip()
    assert len(error.splitlines()) == 1 and "unexpected" not in error and "MemoryError" not in error
    assert f"{packed}: holds more than {MAX_EPISODES_BYTES // 1024**2} MiB of episodes (unpacked)" in error
    assert not (tmp_path / "viewer").exists()


def test_a_line_without_end_is_refused_at_the_line_limit(tmp_path: Path) -> None:
    run = _run(tmp_path / "run")
    packed = _bomb(run / "episodes.jsonl.gz", b"{" + b" " * 1023, 1024**3)  # one line of 1 GiB
    with pytest.raises(EpisodeFileTooLargeError, match=rf"{packed}, line 1: longer than 16 MiB"):
        read_episodes(run)
    assert MAX_LINE_BYTES == 16 * 1024 * 1024


def test_a_file_of_newlines_is_refused_at_the_line_count(tmp_path: Path) -> None:
    run = _run(tmp_path / "run")
    packed = _bomb(run / "episodes.jsonl.gz", b"\n", 1024**3)
    with pytest.raises(EpisodeFileTooLargeError, match=f"{packed}: holds more than {MAX_LINES:,} lines"):
        read_episodes(run)


def test_a_line_over_the_limit_inside_one_chunk_is_refused(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(episode_files, "MAX_LINE_BYTES", 100)
    path = tmp_path / "episodes.jsonl"
    path.write_bytes(b"x" * 100 + b"\n" + b"y" * 101 + b"\n")
    lines = episode_lines(path)
    assert next(lines) == b"x" * 100  # at the limit: read
    with pytest.raises(EpisodeFileTooLargeError, match=f"{path}, line 2: longer than"):
        next(lines)


def test_a_plain_file_over_the_limit_is_refused_too(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(episode_files, "MAX_EPISODES_BYTES", 3 * 1024 * 1024)
    run = _run(tmp_path / "run")
    (run / "episodes.jsonl").write_bytes((b" " * 999 + b"\n") * 4 * 1024)  # 4 MiB of blank lines
    with pytest.raises(EpisodeFileTooLargeError, match=f"{run / 'episodes.jsonl'}: holds more than 3 MiB"):
        read_episodes(run)


@pytest.mark.parametrize(
    "argv",
    [
        ["report", "{run}", "--bootstrap", "0", "--out", "{tmp}/report"],
        ["sample-errors", "{run}", "--out", "{tmp}/sample.json"],
        ["leaderboard", "{run}", "--bootstrap", "0", "--out", "{tmp}/board"],
        ["pack", "--unpack", "{run}"],
        ["verify-run", "{run}"],
    ],
)
def test_every_command_reading_episodes_refuses_a_bomb(
    argv: list[str], tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(episode_files, "MAX_EPISODES_BYTES", 8 * 1024 * 1024)  # the same check, reached sooner
    run = _run(tmp_path / "run")
    packed = _bomb(run / "episodes.jsonl.gz", b" " * 999 + b"\n", 64 * 1024 * 1024)
    assert main([a.format(run=run, tmp=tmp_path) for a in argv]) == 2
    error = capsys.readouterr().err.strip()
    assert len(error.splitlines()) == 1 and "unexpected" not in error
    assert f"{packed}: holds more than 8 MiB of episodes" in error
    assert not (run / "episodes.jsonl").exists()  # nothing was unpacked beside it


def test_unpacking_within_the_limits_is_byte_for_byte(tmp_path: Path) -> None:
    run = tmp_path / "run"
    shutil.copytree(COMMITTED, run)
    packed = gzip.decompress((run / "episodes.jsonl.gz").read_bytes())
    assert read_episode_bytes(run / "episodes.jsonl.gz") == packed
    assert b"\n".join(episode_lines(run / "episodes.jsonl.gz")) == packed
    assert unpack_run(run).changed
    assert (run / "episodes.jsonl").read_bytes() == packed
    assert [r.episode_id for r in read_episodes(run)] == [json.loads(x)["episode_id"] for x in packed.splitlines()]


def test_a_cut_gzip_file_names_the_file(tmp_path: Path) -> None:
    run = _run(tmp_path / "run")
    data = (COMMITTED / "episodes.jsonl.gz").read_bytes()
    (run / "episodes.jsonl.gz").write_bytes(data[: len(data) // 2])
    with pytest.raises(ValueError, match=f"{run / 'episodes.jsonl.gz'}: not a readable gzip file"):
        read_episodes(run)


def test_a_sweeps_progress_poll_stops_counting_where_reading_would_refuse(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """`talkdem sweep` polls each run's episode count; on a bomb it counts no further than the limit a read
    refuses at (here lowered to 4 MiB against 64 MiB unpacked), and never raises."""
    from talkdem.sweeps import work

    monkeypatch.setattr(work, "MAX_EPISODES_BYTES", 4 * 1024 * 1024)
    run = _run(tmp_path / "run")
    _bomb(run / "episodes.jsonl.gz", b" " * 1023 + b"\n", 64 * 1024 * 1024)
    counted = work.done_episodes(run)
    assert 4 * 1024 <= counted <= 5 * 1024  # 1 KiB lines: the 4 MiB bound plus at most one 1 MiB block
