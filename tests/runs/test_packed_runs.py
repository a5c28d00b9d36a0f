"""Packed run directories (`episodes.jsonl.gz`): read like plain ones, packed deterministically, unpacked by
the first episode appended to them and never before, refused when a folder holds both forms."""

from __future__ import annotations

import gzip
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from talkdem.cli import main
from talkdem.runs import EPISODES_FILE, PACKED_EPISODES_FILE, read_episodes, read_header
from talkdem.runs.external import record_plans
from talkdem.runs.pack import pack_run, unpack_run
from talkdem.runs.sampling import select_episodes
from talkdem.runs.shards import merge_runs, split_run
from talkdem.runs.store import run_progress
from talkdem.schema import parse_conditions
from talkdem.sweeps.work import done_episodes
from talkdem.tasks import get_task

SCRIPT = Path(__file__).parent / "run_scripted.py"
SCRIPTED = ["run", "--backend", "scripted", "--model", "m", "--conditions", "clean,intrusion:1", "--limit", "2"]


def _plans(limit: int = 2) -> dict[str, list[str]]:
    episodes = select_episodes(parse_conditions("clean,intrusion:2"), limit)
    return {e.id: list(get_task(e.task_id).reference_plan) for e in episodes}


@pytest.fixture
def plain_run(tmp_path: Path) -> Path:
    run = tmp_path / "run"
    record_plans(_plans(), run, "planner-x")
    return run


def _cut_to(run: Path, keep: int) -> None:
    lines = (run / EPISODES_FILE).read_text().splitlines(keepends=True)
    (run / EPISODES_FILE).write_text("".join(lines[:keep]))  # as if killed after `keep` episodes


def _scripted(out: Path) -> subprocess.CompletedProcess[str]:
    command = [sys.executable, str(SCRIPT), "0", *SCRIPTED, "--no-progress", "--out", str(out)]
    done = subprocess.run(command, capture_output=True, text=True, timeout=300, check=False)
    assert done.returncode == 0, done.stderr
    return done


def _outcomes(run_dir: Path) -> list[tuple[str, tuple[str, ...], bool]]:
    return [(r.episode_id, r.plan, r.success) for r in read_episodes(run_dir)]


def test_a_packed_run_reads_as_the_plain_one_and_packs_to_the_same_bytes(plain_run: Path, tmp_path: Path) -> None:
    plain_bytes = (plain_run / EPISODES_FILE).read_bytes()
    before = read_episodes(plain_run)
    result = pack_run(plain_run)
    packed = plain_run / PACKED_EPISODES_FILE
    assert result.changed and not (plain_run / EPISODES_FILE).exists()
    assert result.size_before == len(plain_bytes) and result.size_after == packed.stat().st_size < len(plain_bytes)
    assert gzip.decompress(packed.read_bytes()) == plain_bytes
    assert read_episodes(plain_run) == before
    assert run_progress(plain_run).complete and run_progress(plain_run).done == len(before)
    assert done_episodes(plain_run) == len(before)
    # No time and no file name in the gzip header: another copy packed later gives identical bytes.
    header = packed.read_bytes()[:10]
    assert header[3] & 0x08 == 0 and header[4:8] == b"\0\0\0\0"
    copy = tmp_path / "copy"
    shutil.copytree(plain_run, copy)
    assert unpack_run(copy).changed and (copy / EPISODES_FILE).read_bytes() == plain_bytes
    assert not (copy / PACKED_EPISODES_FILE).exists()
    pack_run(copy)
    assert (copy / PACKED_EPISODES_FILE).read_bytes() == packed.read_bytes()


def test_a_bad_line_of_a_packed_run_is_named_as_before(plain_run: Path) -> None:
    lines = (plain_run / EPISODES_FILE).read_text().splitlines()
    lines[1] = "{not json"
    (plain_run / PACKED_EPISODES_FILE).write_bytes(gzip.compress(("\n".join(lines) + "\n").encode()))
    (plain_run / EPISODES_FILE).unlink()
    with pytest.raises(ValueError, match=r"episodes\.jsonl\.gz, line 2: not a JSON record"):
        read_episodes(plain_run)
    (plain_run / PACKED_EPISODES_FILE).write_bytes(b"not gzip at all")
    with pytest.raises(ValueError, match=r"episodes\.jsonl\.gz: not a readable gzip file"):
        read_episodes(plain_run)


def test_a_folder_with_both_files_is_refused_by_readers_and_writers(
    plain_run: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    (plain_run / PACKED_EPISODES_FILE).write_bytes(gzip.compress((plain_run / EPISODES_FILE).read_bytes()[:-1]))
    with pytest.raises(ValueError, match=r"holds both episodes\.jsonl and episodes\.jsonl\.gz"):
        read_episodes(plain_run)
    with pytest.raises(ValueError, match="holds both"):
        record_plans(_plans(), plain_run, "planner-x")
    assert main(["report", str(plain_run), "--out", str(plain_run.parent / "report")]) == 2
    error = capsys.readouterr().err.strip()
    assert len(error.splitlines()) == 1 and "episodes.jsonl and episodes.jsonl.gz" in error
    # Different episodes in the two: packing cannot tell which is current, and changes nothing.
    assert main(["pack", str(plain_run)]) == 2
    assert "with different episodes" in capsys.readouterr().err
    assert (plain_run / EPISODES_FILE).exists() and (plain_run / PACKED_EPISODES_FILE).exists()


def test_a_pack_interrupted_between_its_two_steps_is_finished_by_packing_again(plain_run: Path) -> None:
    plain_bytes = (plain_run / EPISODES_FILE).read_bytes()
    (plain_run / PACKED_EPISODES_FILE).write_bytes(gzip.compress(plain_bytes))
    assert not pack_run(plain_run).changed
    assert not (plain_run / EPISODES_FILE).exists() and read_episodes(plain_run)


def test_a_partial_packed_run_is_unpacked_by_its_resume_and_finished(plain_run: Path, tmp_path: Path) -> None:
    whole = [(r.episode_id, r.plan, r.success) for r in read_episodes(plain_run)]
    _cut_to(plain_run, 2)
    assert not pack_run(plain_run).changed, "an incomplete run is packed only with partial"
    assert pack_run(plain_run, partial=True).changed
    record_plans(_plans(), plain_run, "planner-x")  # the resume: two episodes left
    assert not (plain_run / PACKED_EPISODES_FILE).exists()
    assert _outcomes(plain_run) == whole and read_header(plain_run).status == "complete"


def test_resuming_a_packed_run_with_the_runner(tmp_path: Path) -> None:
    whole = tmp_path / "whole"
    _scripted(whole)
    complete = (whole / EPISODES_FILE).read_bytes()
    assert pack_run(whole).changed
    packed = (whole / PACKED_EPISODES_FILE).read_bytes()
    done = _scripted(whole)  # nothing left to run: the run stays packed, untouched
    assert "0 episodes run, 4 resumed" in done.stdout and "unpacked" not in done.stderr
    assert (whole / PACKED_EPISODES_FILE).read_bytes() == packed and not (whole / EPISODES_FILE).exists()
    assert read_header(whole).status == "complete"

    killed = tmp_path / "killed"
    _scripted(killed)
    _cut_to(killed, 1)
    assert pack_run(killed, partial=True).changed
    resumed = _scripted(killed)
    assert "3 episodes run, 1 resumed" in resumed.stdout
    assert resumed.stderr.strip().splitlines() == [
        f"{killed}: unpacked episodes.jsonl.gz to append episodes (`talkdem pack` packs it again)"
    ]
    assert not (killed / PACKED_EPISODES_FILE).exists()
    assert _outcomes(killed) == _outcomes(whole)
    assert [r.episode_id for r in read_episodes(killed)] == [r.episode_id for r in read_episodes(whole)]
    assert len(complete.splitlines()) == 4


def test_packed_shards_merge_and_a_packed_run_splits(tmp_path: Path) -> None:
    run = tmp_path / "run"
    _scripted(run)
    expected = _outcomes(run)
    assert pack_run(run).changed
    shards = split_run(run, 2, tmp_path / "shards")
    assert sum(s.seeded for s in shards) == 4
    for shard in shards:
        assert pack_run(shard.run_dir).changed
    merged = tmp_path / "merged"
    assert merge_runs(merged, [s.run_dir for s in shards]).episodes == 4
    assert _outcomes(merged) == expected and (merged / EPISODES_FILE).is_file()


def test_talkdem_pack_command(plain_run: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    plain_bytes = (plain_run / EPISODES_FILE).read_bytes()
    stray = tmp_path / "stray"
    stray.mkdir()
    assert main(["pack", str(plain_run), str(stray)]) == 2
    assert capsys.readouterr().err.strip() == f"talkdem pack: error: {stray}: not a run directory (no header.json file)"
    assert (plain_run / EPISODES_FILE).exists(), "nothing is packed when one name is wrong"

    assert main(["pack", str(plain_run)]) == 0
    line = capsys.readouterr().out.strip()
    assert line.startswith(f"{plain_run}: packed, ") and line.endswith(" KB") and " -> " in line
    assert main(["pack", str(plain_run)]) == 0
    assert capsys.readouterr().out.strip().startswith(f"{plain_run}: already packed (")
    assert main(["pack", "--unpack", str(plain_run)]) == 0
    assert capsys.readouterr().out.strip().startswith(f"{plain_run}: unpacked, ")
    assert (plain_run / EPISODES_FILE).read_bytes() == plain_bytes

    _cut_to(plain_run, 1)
    assert main(["pack", str(plain_run)]) == 1
    assert capsys.readouterr().err.strip() == (
        f"{plain_run}: not packed, 1 of 4 episodes (INCOMPLETE); --partial packs it anyway"
    )
    assert not (plain_run / PACKED_EPISODES_FILE).exists()
    assert main(["pack", "--partial", str(plain_run)]) == 0 and (plain_run / PACKED_EPISODES_FILE).exists()


def test_scoring_the_same_plans_into_a_complete_packed_run_leaves_it_packed(plain_run: Path) -> None:
    pack_run(plain_run)
    packed = (plain_run / PACKED_EPISODES_FILE).read_bytes()
    assert record_plans(_plans(), plain_run, "planner-x") == 4
    assert (plain_run / PACKED_EPISODES_FILE).read_bytes() == packed and not (plain_run / EPISODES_FILE).exists()
