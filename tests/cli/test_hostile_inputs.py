"""Bad input to any command: one line naming the problem and a non-zero exit, never a traceback and never
an exit 0 for a run that did nothing."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from talkdem.cli import main
from talkdem.tasks import load_tasks


def _fails(argv: list[str], capsys: pytest.CaptureFixture[str]) -> str:
    """Run the CLI in this process; return stderr after checking the exit was a clean refusal."""
    try:
        code = main(argv)
    except SystemExit as exit_:  # argparse refuses a bad option value before the command starts
        code = int(exit_.code or 0)
    error = capsys.readouterr().err
    assert code == 2, f"exit {code} for {argv}: {error}"
    assert "Traceback" not in error
    assert error.strip().count("\n") <= 1 or error.startswith("usage:"), error
    return error


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["run", "--limit", "0"], "--limit: must be at least 1, got 0"),
        (["run", "--limit", "-3"], "--limit: must be at least 1, got -3"),
        (["run", "--max-steps", "0"], "--max-steps: must be at least 1"),
        (["run", "--limit", "x"], "'x' is not a whole number"),
        (["run", "--conditions", ","], "no condition in ','"),
        (["run", "--conditions", "intrusion:7"], "the level must be 1, 2 or 3"),
        (["demo", "--tasks", "0"], "--tasks: must be at least 1"),
        (["run", "--backend", "hf", "--base-url", "http://127.0.0.1:9/v1"], "--base-url is for --backend openai"),
        (["run", "--backend", "openai", "--model", "m", "--model-arg", "threads=2"], "the openai backend has no such"),
        (["run", "--strategy", "care", "--strategy-arg", "order=last"], "the care strategy's 'order' takes one of"),
        (["build", "--limit", "-1"], "--limit: must be at least 1"),
        (["push", "--repo", "not a repo", "--dry-run"], "is not a Hub repository id"),
        (["report", "x", "--bootstrap", "-5"], "--bootstrap: must be 0 (no intervals) or at least 40"),
        (["leaderboard", "x", "--bootstrap", "-5"], "--bootstrap: must be 0 (no intervals) or at least 40"),
        (["report", "x", "--reference-strategy", "magic"], "unknown strategy 'magic'"),
        (["push", "--repo", "org/name/extra", "--dry-run"], "is not a Hub repository id"),
    ],
)
def test_bad_option_values_are_refused(argv: list[str], message: str, capsys: pytest.CaptureFixture[str]) -> None:
    assert message in _fails(argv, capsys)


def test_out_under_an_existing_file(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    blocker = tmp_path / "file"
    blocker.write_text("")
    plans = tmp_path / "plans.jsonl"
    task = load_tasks("benchmark")[0]
    plans.write_text(json.dumps({"episode_id": f"{task.task_id}:clean:0", "plan": ["done"]}) + "\n")
    error = _fails(["score", str(plans), "--out", str(blocker / "run")], capsys)
    assert "Not a directory" in error and str(blocker) in error


def test_out_that_is_a_file(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    target = tmp_path / "file"
    target.write_text("keep me")
    plans = tmp_path / "plans.jsonl"
    task = load_tasks("benchmark")[0]
    plans.write_text(json.dumps({"episode_id": f"{task.task_id}:clean:0", "plan": ["done"]}) + "\n")
    error = _fails(["score", str(plans), "--out", str(target)], capsys)
    assert "is not a folder" in error or "Not a directory" in error
    assert target.read_text() == "keep me"


def test_a_plan_nested_too_deeply(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    plan = tmp_path / "plan.json"
    plan.write_text("[" * 100_000 + "]" * 100_000)
    task = load_tasks("benchmark")[0]
    assert "nested too deeply" in _fails(["simulate", "--task", task.task_id, "--plan-file", str(plan)], capsys)


def test_an_unreadable_plan_file(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    task = load_tasks("benchmark")[0]
    error = _fails(["simulate", "--task", task.task_id, "--plan-file", str(tmp_path)], capsys)
    assert "cannot read plan file" in error
    error = _fails(["score", str(tmp_path), "--out", str(tmp_path / "run")], capsys)
    assert "cannot read the plan file" in error


def test_a_plan_that_is_a_string(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    plan = tmp_path / "plan.json"
    plan.write_text(json.dumps("find an apple"))
    task = load_tasks("benchmark")[0]
    error = _fails(["simulate", "--task", task.task_id, "--plan-file", str(plan)], capsys)
    assert "a plan must be a list of skill strings" in error and "got a string" in error


def test_a_model_file_that_does_not_exist(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    missing = tmp_path / "no-such-model.gguf"
    error = _fails(
        ["run", "--backend", "llamacpp", "--model", str(missing), "--limit", "1", "--out", str(tmp_path / "r")], capsys
    )
    assert "no-such-model.gguf" in error
    assert not (tmp_path / "r").exists(), "nothing is created before the model loads"


def test_an_unreachable_server(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    argv = [
        "run", "--backend", "openai", "--base-url", "http://127.0.0.1:9/v1", "--model", "m",
        "--planner", "generative", "--limit", "1", "--conditions", "clean", "--out", str(tmp_path / "r"),
        "--no-progress",
    ]  # fmt: skip
    error = _fails(argv, capsys)
    assert "127.0.0.1:9" in error


# -- every error names its file (and line where there is one) -------------------------------------------------
def _data_copy(tmp_path: Path) -> Path:
    import shutil

    from talkdem.paths import data_dir

    copy = tmp_path / "data"
    shutil.copytree(data_dir(), copy)
    return copy


def test_a_cache_that_is_a_folder_or_not_sqlite_names_the_file(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    served = ["--backend", "openai", "--base-url", "http://127.0.0.1:9/v1", "--model", "m", "--planner", "generative"]
    argv = ["run", *served, "--limit", "1", "--conditions", "clean", "--out", str(tmp_path / "r"), "--no-progress"]
    error = _fails([*argv, "--cache", str(tmp_path)], capsys)
    assert f"{tmp_path}: is a folder; --cache takes a file" in error
    corrupt = tmp_path / "cache.sqlite"
    corrupt.write_bytes(b"SQLite format 3\x00" + bytes(range(256)) * 40)
    error = _fails([*argv, "--cache", str(corrupt)], capsys)
    assert f"{corrupt}: not a usable SQLite result cache" in error and "unexpected" not in error
    assert "127.0.0.1:9" not in error, "refused before any model work"


def test_bad_yaml_in_the_dataset_card_names_the_file_and_line(tmp_path: Path) -> None:
    from talkdem.instructions import dataset_configs

    copy = _data_copy(tmp_path)
    lines = (copy / "README.md").read_text().splitlines()
    bad_line = next(i for i, line in enumerate(lines) if line.startswith("configs:")) + 2
    lines[bad_line - 1] = "  data_files: [unclosed"
    (copy / "README.md").write_text("\n".join(lines) + "\n")
    with pytest.raises(ValueError, match="does not parse") as refused:
        dataset_configs(copy)
    assert str(refused.value).startswith(f"{copy / 'README.md'}:")
    (copy / "README.md").write_text("---\nconfigs:\n- name: x\n---\n")
    with pytest.raises(ValueError, match=r"README\.md: config 1 of the front matter needs `config_name`"):
        dataset_configs.__wrapped__(copy)


def test_a_broken_worked_examples_line_names_the_file_and_line(tmp_path: Path) -> None:
    from talkdem.planner.examples import task_type_examples

    copy = _data_copy(tmp_path)
    path = copy / "prompts" / "saycan_examples.jsonl"
    lines = path.read_text().splitlines()
    lines[2] = lines[2][:-5]  # a truncated line
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(ValueError, match=r"saycan_examples\.jsonl:3: not a JSON line"):
        task_type_examples(copy)
    lines[2] = json.dumps({"instruction": "x", "reference_plan": "find a box"})
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(ValueError, match=r"saycan_examples\.jsonl:3: an example needs"):
        task_type_examples.__wrapped__(copy)


def test_a_corrupted_parquet_page_names_the_file(tmp_path: Path) -> None:
    from talkdem.instructions import load_instructions

    copy = _data_copy(tmp_path)
    target = copy / "intrusion" / "level_2.parquet"
    data = bytearray(target.read_bytes())
    middle = len(data) // 3
    data[middle : middle + 64] = bytes(64)  # inside a data page, far from the footer
    target.write_bytes(bytes(data))
    with pytest.raises(ValueError, match="cannot read this Parquet file") as refused:
        load_instructions(copy)
    assert str(refused.value).startswith(str(target))


# -- no flag is silently ignored --------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["select", "--saved", "--write"], "--saved prints the saved table, --write recomputes"),
        (["tasks", "--full", "--format", "table"], "--full applies to --format jsonl"),
        (["tasks", "--full"], "--full applies to --format jsonl"),
        (["build", "--out", ""], "--out: must name a folder, got an empty string"),
        (["report", "x", "--out", " "], "--out: must name a folder"),
        (["run", "--limit", "1", "--conditions", "clean", "--shard", "5/9"], "--shard 5/9: this shard is empty"),
    ],
)
def test_flags_that_would_be_ignored_are_refused(
    argv: list[str], message: str, capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    before = sorted(Path.cwd().iterdir())
    assert message in _fails(argv, capsys)
    assert sorted(Path.cwd().iterdir()) == before, "nothing written into the current folder"
