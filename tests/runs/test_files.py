"""`talkdem.files`: the one atomic write and the one file lock, used by runs, builders, caches and the model
catalog."""

from __future__ import annotations

from pathlib import Path

import pytest

from talkdem.files import exclusive_lock, replace_file, replacing


def test_a_file_is_replaced_whole_and_no_scratch_is_left(tmp_path: Path) -> None:
    target = tmp_path / "header.json"
    replace_file(target, "first ü\n")
    replace_file(target, b"second\n")
    assert target.read_bytes() == b"second\n"
    replace_file(target, "dritte ü\n")
    assert target.read_bytes() == "dritte ü\n".encode()
    assert [p.name for p in tmp_path.iterdir()] == ["header.json"]


def test_an_error_while_writing_leaves_the_old_file_and_no_scratch(tmp_path: Path) -> None:
    target = tmp_path / "shard.npz"
    target.write_bytes(b"old")
    with pytest.raises(RuntimeError, match="writer failed"), replacing(target) as scratch:
        scratch.write_bytes(b"half")
        assert scratch.name.startswith(".") and not scratch.name.endswith(".npz")  # no reader's pattern sees it
        raise RuntimeError("writer failed")
    assert target.read_bytes() == b"old" and [p.name for p in tmp_path.iterdir()] == ["shard.npz"]


def test_a_held_lock_refuses_a_second_holder_with_the_callers_error(tmp_path: Path) -> None:
    checkpoint = tmp_path / "checkpoint.jsonl"
    checkpoint.write_text("kept\n")
    for locked in (checkpoint, tmp_path):  # a file (its content untouched) and a folder
        busy = ValueError(f"{locked}: in use")
        with (
            exclusive_lock(locked, in_use=busy),
            pytest.raises(ValueError, match="in use"),
            exclusive_lock(locked, busy),
        ):
            pass
        with exclusive_lock(locked, in_use=ValueError("free again")):  # released when the block ended
            pass
    assert checkpoint.read_text() == "kept\n"
    with exclusive_lock(tmp_path / "new.lock"):  # a missing lock file is created; without in_use it waits
        assert (tmp_path / "new.lock").is_file()
