"""What people hand the viewer and the report besides runs: error samples and labels files that are not UTF-8 or
hold NaN are one line naming the file; `view --out ''` is refused like report's; runs that would share a label
get their key, labels and samples name runs by key (so they reach the right run whatever the order or company);
a model with a very long name still gets file names the file system takes."""

from __future__ import annotations

import json
import shutil
from pathlib import Path
from typing import Any

import pytest
from metrics_helpers import BOOK, LAMP, clean_id, failing, pattern_id, reference, write_run
from viewer_browser import index_of

from talkdem.cli import main
from talkdem.paths import MAX_STEM, file_stem
from talkdem.report import score_runs, unique_stems
from talkdem.report.runs import run_key, run_labels
from talkdem.runs import read_header
from talkdem.viewer import load_runs, read_labels, read_sample, sample_errors, write_viewer


def _fails(argv: list[str], capsys: pytest.CaptureFixture[str]) -> str:
    try:
        code = main(argv)
    except SystemExit as exit_:  # argparse refuses a bad option value before the command starts
        code = int(exit_.code or 0)
    error = capsys.readouterr().err.strip()
    assert code == 2, error
    assert "Traceback" not in error and "unexpected" not in error
    assert len(error.splitlines()) == 1 or error.startswith("usage:"), error
    return error.splitlines()[-1]


def _plans(tasks: tuple[str, ...] = (BOOK,)) -> dict[str, list[str]]:
    """Each task solved clean and failed under intrusion, level 1: one failure to sample and label per task."""
    out: dict[str, list[str]] = {}
    for task in tasks:
        out[clean_id(task)] = reference(task)
        out[pattern_id(task, "intrusion", 1)] = failing(task)
    return out


@pytest.fixture(scope="module")
def twins(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    """Two different runs of one model and strategy: the labels the report gives them would be the same."""
    root = tmp_path_factory.mktemp("twins")
    return write_run(root / "first", _plans((BOOK,))), write_run(root / "second", _plans((BOOK, LAMP)))


# ---- sample and labels files ----


@pytest.mark.parametrize(
    ("content", "message"),
    [
        (
            b'{"schema": "talkdem-error-sample/1",\n"seed": 0, "per_condition": 3, "episodes": ["\xff"]}',
            "line 2: not UTF-8",
        ),
        (b'{"schema": "talkdem-error-sample/1", "seed": NaN, "per_condition": 3, "episodes": []}', "NaN"),
        (b'{"schema": "talkdem-error-sample/1",\n"seed": 0,\n"per_condition": Infinity, "episodes": []}', "line 3"),
        (
            b'{"schema": "talkdem-error-sample/1", "seed": 0, "per_condition": 3, "x": -Infinity, "episodes": []}',
            "-Infinity",
        ),
        (b'{"schema": "talkdem-error-sample/1", "seed": 0, "per_condition": 0, "episodes": []}', "'per_condition'"),
        (b'{"schema": "talkdem-error-sample/1", "seed": 1.5, "per_condition": 3, "episodes": []}', "'seed'"),
        (
            b'{"schema": "talkdem-error-sample/1", "seed": 0, "per_condition": 3, "episodes": [{"run": "a", '
            b'"episode_id": "b", "automatic": ["x"]}]}',
            "episode 1: field 'automatic'",
        ),
        (
            b'{"schema": "talkdem-error-sample/1", "seed": 0, "per_condition": 3, "episodes": [{"run": "a", '
            b'"episode_id": "b", "run_key": 7}]}',
            "episode 1: field 'run_key'",
        ),
        (b'{"schema": "talkdem-error-sample/1", "seed": ' + b"1" * 5000 + b"}", "a number too long"),
        (b"[" * 100_000, "nested too deeply"),
    ],
)
def test_a_bad_sample_file_is_one_line_naming_it(
    content: bytes, message: str, twins: tuple[Path, Path], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    sample = tmp_path / "sample.json"
    sample.write_bytes(content)
    error = _fails(["view", str(twins[0]), "--sample", str(sample), "--out", str(tmp_path / "v")], capsys)
    assert str(sample) in error and message in error
    assert not (tmp_path / "v").exists()


def test_a_quoted_nan_is_text_not_a_number(tmp_path: Path) -> None:
    sample = tmp_path / "sample.json"
    sample.write_text(
        '{"schema": "talkdem-error-sample/1", "seed": 0, "per_condition": 1, "episodes": [], "note": "NaN"}'
    )
    assert read_sample(sample)["note"] == "NaN"


@pytest.mark.parametrize(
    ("content", "message"),
    [
        (b'{"schema": "talkdem-error-labels/1", "labels": [{"run": "caf\xe9"}]}', "line 1: not UTF-8"),
        (b'{"schema": "talkdem-error-labels/1",\n"viewer": NaN, "labels": []}', "line 2: holds NaN"),
    ],
)
def test_a_bad_labels_file_is_one_line_naming_it(
    content: bytes, message: str, twins: tuple[Path, Path], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    labels = tmp_path / "labels.json"
    labels.write_bytes(content)
    argv = ["report", str(twins[0]), "--labels", str(labels), "--no-plots", "--bootstrap", "0"]
    error = _fails([*argv, "--out", str(tmp_path / "r")], capsys)
    assert str(labels) in error and message in error


# ---- --out '' ----


@pytest.mark.parametrize("command", ["view", "sample-errors"])
def test_an_empty_out_is_refused(
    command: str,
    twins: tuple[Path, Path],
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
) -> None:
    monkeypatch.chdir(tmp_path)
    error = _fails([command, str(twins[0]), "--out", ""], capsys)
    assert "--out" in error and "empty string" in error
    assert list(tmp_path.iterdir()) == []  # nothing written into the current folder


# ---- run labels and keys ----


def test_runs_that_would_share_a_label_get_their_keys_whatever_the_order(twins: tuple[Path, Path]) -> None:
    first, second = twins
    forward = load_runs([first, second])
    backward = load_runs([second, first])
    assert forward[0].label != forward[1].label
    assert {r.run_dir: r.label for r in forward} == {r.run_dir: r.label for r in backward}
    for run in forward:
        assert run.label == f"tiny-model / Vanilla [{run.key}]"
        assert run.key == run_key(run.run_dir, run.header)
    assert load_runs([first])[0].label == "tiny-model / Vanilla"  # alone: nothing to tell apart
    scored = score_runs([second, first], bootstrap=0)
    assert [r.label for r in scored] == [backward[0].label, backward[1].label]  # the report names them alike


def test_a_strategy_named_like_a_suffixed_label_does_not_collide(twins: tuple[Path, Path], tmp_path: Path) -> None:
    first, second = twins
    key = run_key(first, read_header(first))
    third = write_run(tmp_path / "third", _plans(), strategy=f"Vanilla [{key}]")
    dirs = [first, second, third]
    labels = run_labels(dirs, [read_header(d) for d in dirs])
    assert len(set(labels)) == 3
    assert all(label.endswith(f"[{run_key(d, read_header(d))}]") for d, label in zip(dirs, labels, strict=True))


def test_one_run_given_twice_is_refused(twins: tuple[Path, Path], capsys: pytest.CaptureFixture[str]) -> None:
    error = _fails(["view", str(twins[0]), str(twins[0]), "--out", "unused"], capsys)
    assert "the same run as" in error and str(twins[0]) in error


def test_the_sample_reaches_the_same_runs_in_another_order(twins: tuple[Path, Path], tmp_path: Path) -> None:
    first, second = twins
    sample = sample_errors(load_runs([first, second]), 1, seed=0).to_json()
    assert {e["run_key"] for e in sample["episodes"]} == {run_key(d, read_header(d)) for d in twins}
    runs = load_runs([second, first])
    files = write_viewer(runs, tmp_path / "viewer", sample=sample)
    index = index_of(files.folder)
    fields = index["fields"]
    sampled = {
        (index["runs"][row[fields.index("run")]]["key"], row[fields.index("episode_id")])
        for row in index["rows"]
        if row[fields.index("sampled")]
    }
    assert sampled == {(e["run_key"], e["episode_id"]) for e in sample["episodes"]}
    assert [r["key"] for r in index["runs"]] == [r.key for r in runs]


def _labels(path: Path, entries: list[dict[str, Any]]) -> Path:
    path.write_text(json.dumps({"schema": "talkdem-error-labels/1", "labels": entries}), encoding="utf-8")
    return path


def test_labels_go_to_the_run_their_key_names(twins: tuple[Path, Path], tmp_path: Path) -> None:
    first, second = twins
    lamp = pattern_id(LAMP, "intrusion", 1)  # only the second run has it
    key = run_key(second, read_header(second))
    # The viewer showed both runs: its label for the second carries the key; the report shows the second alone.
    shown = next(r.label for r in load_runs([first, second]) if r.run_dir == second)
    entry = {"run": shown, "run_key": key, "episode_id": lamp, "type": "subgoal_omission"}
    (label,) = read_labels(_labels(tmp_path / "l.json", [entry]), score_runs([second], bootstrap=0))
    assert (label.run, label.episode_id) == ("tiny-model / Vanilla", lamp)
    # Both runs reported, in the other order: still the second run's label, never the first's.
    (label,) = read_labels(_labels(tmp_path / "l.json", [entry]), score_runs([second, first], bootstrap=0))
    assert label.run == shown
    with pytest.raises(ValueError, match=r"l.json: label 1 .*unknown run key 'ffffffff'"):
        read_labels(_labels(tmp_path / "l.json", [{**entry, "run_key": "ffffffff"}]), score_runs([first], bootstrap=0))
    with pytest.raises(ValueError, match=r"unknown episode id"):  # the first run has no LAMP episode
        read_labels(
            _labels(tmp_path / "l.json", [{**entry, "run_key": run_key(first, read_header(first))}]),
            score_runs([first], bootstrap=0),
        )


# ---- long model names ----


def test_a_long_model_name_gets_bounded_file_names(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    model = "org/" + "a-very-long-model-name-" * 20  # 464 characters
    run = write_run(tmp_path / "run", _plans(), model=model)
    out = tmp_path / "report"
    assert main(["report", str(run), "--bootstrap", "0", "--out", str(out)]) == 0, capsys.readouterr().err
    written = [p for p in out.rglob("*") if p.is_file()]
    assert any(p.parent.name == "scores" for p in written) and any(p.name.startswith("heatmap_") for p in written)
    assert all(len(p.name.encode()) <= 255 for p in written)
    board = tmp_path / "board"
    assert main(["leaderboard", str(run), "--bootstrap", "0", "--out", str(board)]) == 0, capsys.readouterr().err
    assert all(len(part.encode()) <= 255 for p in board.rglob("*") for part in p.relative_to(board).parts)


def test_file_stems_are_bounded_and_stay_apart() -> None:
    long_a, long_b = "m" * 300 + " / CARE", "m" * 300 + " / Vanilla"
    stems = unique_stems([long_a, long_b, "short / CARE"])
    assert all(len(s) <= MAX_STEM + 9 for s in stems)
    assert len(set(stems)) == 3 and stems[2] == "short_CARE"
    assert file_stem(long_a, "run") != file_stem(long_b, "run")
    assert len(file_stem(long_a, "run")) == MAX_STEM
    assert file_stem("x" * MAX_STEM, "run") == "x" * MAX_STEM  # at the limit: kept as it is


def test_a_run_and_its_extension_beside_it_are_told_apart(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    """A run kept beside its extension (`runs/X` holding some conditions of `runs/levels/X`, as a run extended to
    more levels is kept): one folder name, one start time, told apart by the folder holding them."""
    committed = Path(__file__).resolve().parent.parent.parent / "results/paper/qwen2.5-coder-0.5b-care"
    level3, levels = tmp_path / "runs/qwen2.5-coder-0.5b-care", tmp_path / "runs/levels/qwen2.5-coder-0.5b-care"
    for folder in (level3, levels):
        folder.mkdir(parents=True)
        shutil.copy(committed / "header.json", folder / "header.json")
    headers = [read_header(level3), read_header(levels)]
    assert headers[0].created == headers[1].created
    labels = run_labels([level3, levels], headers)
    assert len(set(labels)) == 2 and all(label.startswith("qwen2.5-coder-0.5b / CARE [") for label in labels)
    monkeypatch.chdir(tmp_path)  # a key does not depend on how the folder is named on the command line
    assert run_key(Path("runs/levels/qwen2.5-coder-0.5b-care"), headers[1]) == run_key(levels, headers[1])
