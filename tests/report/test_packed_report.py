"""A packed run (`talkdem pack`) is reported, ranked and viewed exactly as the plain run it was packed from."""

from __future__ import annotations

from pathlib import Path

import pytest
from metrics_helpers import BOOK, LAMP, clean_id, failing, pattern_id, reference, write_run

from talkdem.cli import main
from talkdem.runs import EPISODES_FILE, PACKED_EPISODES_FILE
from talkdem.runs.pack import pack_run
from talkdem.schema import PATTERN_CONFIGS
from talkdem.viewer import load_runs


def _plans() -> dict[str, list[str]]:
    out = {clean_id(t): reference(t) for t in (BOOK, LAMP)}
    for task in (BOOK, LAMP):
        for pattern in PATTERN_CONFIGS:
            for level in (1, 2, 3):
                out[pattern_id(task, pattern, level)] = reference(task) if level < 3 else failing(task)
    return out


def _files(folder: Path) -> dict[str, bytes]:
    return {p.relative_to(folder).as_posix(): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()}


def _outputs(run: Path, out: Path) -> tuple[dict[str, bytes], dict[str, bytes]]:
    assert main(["report", str(run), "--out", str(out / "report"), "--bootstrap", "50", "--no-plots"]) == 0
    assert main(["leaderboard", str(run), "--out", str(out / "board"), "--bootstrap", "0"]) == 0
    return _files(out / "report"), _files(out / "board")


def test_report_leaderboard_and_viewer_of_a_packed_run_equal_the_plain_ones(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    run = write_run(tmp_path / "run", _plans(), strategy="care")
    plain = _outputs(run, tmp_path / "plain")
    viewed = load_runs([run])
    assert pack_run(run).changed and not (run / EPISODES_FILE).exists()
    packed = _outputs(run, tmp_path / "packed")
    assert (run / PACKED_EPISODES_FILE).is_file() and not (run / EPISODES_FILE).exists(), "reading never unpacks"
    assert packed[0] == plain[0] and packed[1] == plain[1]
    assert any(name.endswith(".md") for name in plain[0])
    assert load_runs([run]) == viewed
