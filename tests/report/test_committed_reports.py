"""The committed reports and leaderboard are what today's code computes from the committed runs.

A report is the number people quote; one built by older code is a stale result that nothing else would notice.
Each report's tables and score files are rebuilt here from the run folders its README names, in the same order,
and compared: text (tables, pages) byte for byte, since it prints rounded figures; JSON value by value, floats to
1e-9 relative, since numpy's reductions may differ in the last bits between CPUs (plots are left out: their pixels
depend on the machine's fonts, and they are drawn from the same scores).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from talkdem.cli import main
from talkdem.paths import repo_root

PAPER = "results/paper"
CLARIFY = "results/clarify"
REPORTS = {
    f"{PAPER}/report": [
        f"{PAPER}/qwen2.5-coder-0.5b-vanilla",
        f"{PAPER}/qwen2.5-coder-0.5b-ap",
        f"{PAPER}/qwen2.5-coder-0.5b-cot",
        f"{PAPER}/qwen2.5-coder-0.5b-icl",
        f"{PAPER}/qwen2.5-coder-0.5b-tocc",
        f"{PAPER}/qwen2.5-coder-0.5b-care",
        f"{PAPER}/qwen2.5-coder-1.5b-vanilla",
        f"{PAPER}/qwen2.5-coder-1.5b-care",
    ],
    f"{CLARIFY}/report": [
        f"{PAPER}/qwen2.5-coder-0.5b-vanilla",
        f"{CLARIFY}/oracle/qwen2.5-coder-0.5b-vanilla",
        f"{CLARIFY}/in-pattern/qwen2.5-coder-0.5b-vanilla",
        f"{PAPER}/qwen2.5-coder-0.5b-care",
        f"{CLARIFY}/oracle/qwen2.5-coder-0.5b-care",
        f"{CLARIFY}/in-pattern/qwen2.5-coder-0.5b-care",
    ],
}


def _same(a: object, b: object) -> bool:
    if isinstance(a, float) or isinstance(b, float):
        return isinstance(a, int | float) and isinstance(b, int | float) and math.isclose(a, b, rel_tol=1e-9)
    if isinstance(a, dict) and isinstance(b, dict):
        return a.keys() == b.keys() and all(_same(a[key], b[key]) for key in a)
    if isinstance(a, list) and isinstance(b, list):
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b, strict=True))
    return a == b


def _differ(name: str, rebuilt: bytes, committed: bytes) -> bool:
    if name.endswith(".json"):
        return not _same(json.loads(rebuilt), json.loads(committed))
    return rebuilt != committed


def _files(folder: Path) -> dict[str, bytes]:
    return {
        str(path.relative_to(folder)): path.read_bytes()
        for part in ("tables", "scores")
        for path in sorted((folder / part).rglob("*"))
        if path.is_file()
    }


@pytest.mark.parametrize("report", sorted(REPORTS))
def test_a_committed_report_is_what_the_code_computes_from_its_runs(
    report: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    root = repo_root()
    runs = REPORTS[report]
    readme = (root / report).parent / "README.md"
    # The runs are named as the README tells a reader to rebuild the report (README lines wrap anywhere).
    assert all(run.rsplit("/", 1)[-1] in readme.read_text(encoding="utf-8") for run in runs)
    assert main(["report", *(str(root / run) for run in runs), "--no-plots", "--out", str(tmp_path)]) == 0
    capsys.readouterr()
    rebuilt, committed = _files(tmp_path), _files(root / report)
    assert sorted(rebuilt) == sorted(committed)
    assert [name for name in sorted(rebuilt) if _differ(name, rebuilt[name], committed[name])] == []


def test_the_committed_leaderboard_is_what_the_code_computes_from_its_runs(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    root = repo_root()
    assert main(["leaderboard", *(str(root / run) for run in REPORTS[f"{PAPER}/report"]), "--out", str(tmp_path)]) == 0
    capsys.readouterr()
    committed = root / PAPER / "leaderboard"
    files = sorted(path.relative_to(committed) for path in committed.rglob("*") if path.is_file())
    assert files == sorted(path.relative_to(tmp_path) for path in tmp_path.rglob("*") if path.is_file())
    changed = [
        name for name in files if _differ(str(name), (tmp_path / name).read_bytes(), (committed / name).read_bytes())
    ]
    assert changed == []


def test_json_values_are_compared_to_the_last_bits_and_text_exactly() -> None:
    assert not _differ("a.json", b'{"x": [0.30000000000000004, 1]}', b'{"x": [0.3, 1]}')
    assert _differ("a.json", b'{"x": [0.31, 1]}', b'{"x": [0.3, 1]}')
    assert _differ("a.json", b'{"x": [0.3, 1], "y": 1}', b'{"x": [0.3, 1]}')
    assert _differ("a.md", b"| 0.30 |", b"| 0.31 |")
