"""Shard slicing: deterministic, disjoint, covering, balanced; bad shard specifications refused; a run under
way split into seeded shards merges back into the run it would have been."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from talkdem.cli import main
from talkdem.runs import read_episodes, read_header
from talkdem.runs.sampling import select_episodes
from talkdem.runs.shards import Shard, parse_shard, shard_folder, shard_of, split_run
from talkdem.schema import parse_conditions


def test_shards_partition_the_selection_in_its_order() -> None:
    episodes = select_episodes(parse_conditions(None), 7)
    parts = [shard_of(episodes, Shard(i, 3)) for i in (1, 2, 3)]
    ids = [[e.id for e in part] for part in parts]
    assert sorted(i for part in ids for i in part) == sorted(e.id for e in episodes), (
        "every episode in exactly one shard"
    )
    assert max(map(len, ids)) - min(map(len, ids)) <= 1
    order = {e.id: k for k, e in enumerate(episodes)}
    assert all([order[i] for i in part] == sorted(order[i] for i in part) for part in ids)
    assert ids == [[e.id for e in shard_of(list(reversed(episodes)), Shard(i, 3))][::-1] for i in (1, 2, 3)]


@pytest.mark.parametrize("text", ["0/2", "3/2", "1", "a/b", "1/2/3", "-1/2", "1/0"])
def test_bad_shards_are_refused(text: str) -> None:
    with pytest.raises(ValueError, match="must be I/N"):
        parse_shard(text)


def test_parse_shard() -> None:
    assert parse_shard("2/4") == Shard(2, 4) and str(Shard(2, 4)) == "2/4"


SCRIPT = Path(__file__).parent / "run_scripted.py"


def _run(out: Path, conditions: str, *extra: str) -> str:
    command = [sys.executable, str(SCRIPT), "0", "run", "--backend", "scripted", "--model", "m"]
    command += ["--conditions", conditions, "--limit", "2", "--no-progress", "--out", str(out), *extra]
    done = subprocess.run(command, capture_output=True, text=True, timeout=300, check=False)
    assert done.returncode == 0, done.stderr
    return done.stdout


def _outcomes(run_dir: Path) -> list[tuple[str, tuple[str, ...], bool]]:
    return [(r.episode_id, r.plan, r.success) for r in read_episodes(run_dir)]


def test_a_run_under_way_splits_into_seeded_shards_that_merge_into_the_whole_run(tmp_path: Path) -> None:
    started = tmp_path / "started"
    _run(started, "clean")  # 2 episodes finished; the run now grows to intrusion:1 as well
    shards = split_run(started, 2, tmp_path / "shards", conditions="clean,intrusion:1")
    assert [s.run_dir for s in shards] == [shard_folder(tmp_path / "shards", Shard(i, 2)) for i in (1, 2)]
    assert sum(s.seeded for s in shards) == 2 and sum(s.planned for s in shards) == 4
    for shard in shards:
        output = _run(shard.run_dir, "clean,intrusion:1", "--shard", str(shard.shard))
        assert f"{shard.planned - shard.seeded} episodes run, {shard.seeded} resumed" in output
    merged = tmp_path / "merged"
    assert main(["merge", str(merged), *(str(s.run_dir) for s in shards)]) == 0
    whole = tmp_path / "whole"
    _run(whole, "clean,intrusion:1")
    assert _outcomes(merged) == _outcomes(whole)
    assert read_header(merged).config["conditions"] == read_header(whole).config["conditions"]
    assert set(_outcomes(started)) <= set(_outcomes(merged))  # the finished episodes were not run again


def test_splits_that_would_lose_or_mix_episodes_are_refused(tmp_path: Path) -> None:
    started = tmp_path / "started"
    _run(started, "clean")
    with pytest.raises(ValueError, match="is not in the selection to split"):
        split_run(started, 2, tmp_path / "a", conditions="intrusion:1")
    with pytest.raises(ValueError, match="at least 2 shards"):
        split_run(started, 1, tmp_path / "b")
    (tmp_path / "full").mkdir()
    (tmp_path / "full" / "mine.txt").write_text("not yours")
    with pytest.raises(ValueError, match="not an empty folder"):
        split_run(started, 2, tmp_path / "full")
    assert (tmp_path / "full" / "mine.txt").read_text() == "not yours"
    shards = split_run(started, 2, tmp_path / "c")
    with pytest.raises(ValueError, match="merge the shards and split the merge"):
        split_run(shards[0].run_dir, 2, tmp_path / "d")


def test_the_split_command_says_how_to_go_on(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    started = tmp_path / "started"
    _run(started, "clean")
    assert main(["split", str(started), "--shards", "2", "--out", str(tmp_path / "s")]) == 0
    printed = capsys.readouterr().out
    assert "--shard 1/2 --out" in printed and "talkdem merge MERGED_DIR" in printed
    assert main(["split", str(tmp_path / "s" / "shard-1-of-2"), "--shards", "2", "--out", str(tmp_path / "t")]) == 2
    error = capsys.readouterr().err
    assert "merge the shards" in error and len(error.strip().splitlines()) == 1 and "Traceback" not in error
