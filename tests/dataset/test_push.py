"""`talkdem push`: what it would upload, checked on a local folder (no network)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from builders.push import push, upload_plan
from talkdem.cli import main


def make_folder(root: Path) -> Path:
    names = ["README.md", "build_stats.json", "clean/test.parquet", "intrusion/level_1.parquet"]
    names += ["tasks/benchmark.parquet", "tasks/benchmark.jsonl", "selection/diversity.md", "notes.txt"]
    for name in names:
        path = root / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text("x")
    return root


def test_upload_plan_keeps_card_parquet_and_reports(tmp_path: Path) -> None:
    plan = upload_plan(make_folder(tmp_path))
    assert plan == [
        "README.md",
        "build_stats.json",
        "clean/test.parquet",
        "intrusion/level_1.parquet",
        "selection/diversity.md",
        "tasks/benchmark.jsonl",
        "tasks/benchmark.parquet",
    ]


def test_upload_plan_needs_a_card(tmp_path: Path) -> None:
    with pytest.raises(FileNotFoundError, match=r"README\.md"):
        upload_plan(tmp_path)


def test_push_calls_upload_folder(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    calls: dict[str, Any] = {}

    class FakeApi:
        def create_repo(self, repo_id: str, **kwargs: Any) -> None:
            calls["create"] = (repo_id, kwargs)

        def upload_folder(self, **kwargs: Any) -> str:
            calls["upload"] = kwargs
            return "https://example.invalid/commit/1"

    monkeypatch.setattr("huggingface_hub.HfApi", FakeApi)
    folder = make_folder(tmp_path)
    assert push(folder, "org/talk-dem") == "https://example.invalid/commit/1"
    assert calls["create"] == ("org/talk-dem", {"repo_type": "dataset", "private": False, "exist_ok": True})
    upload = calls["upload"]
    assert upload["repo_id"] == "org/talk-dem" and upload["repo_type"] == "dataset"
    assert upload["folder_path"] == str(folder)
    from huggingface_hub.utils import filter_repo_objects  # type: ignore[attr-defined]

    files = sorted(p.relative_to(folder).as_posix() for p in folder.rglob("*") if p.is_file())
    assert list(filter_repo_objects(files, allow_patterns=upload["allow_patterns"])) == upload_plan(folder)


def test_push_refuses_a_bad_repo_name(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="ORG/NAME"):
        push(make_folder(tmp_path), "talk-dem")


def test_cli_dry_run_lists_the_plan(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["push", "--repo", "org/name", "--data", str(make_folder(tmp_path)), "--dry-run"]) == 0
    assert capsys.readouterr().out.split() == upload_plan(tmp_path)
