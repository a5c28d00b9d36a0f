"""`talkdem push --leaderboard`: the Space and the results dataset, on a local folder. Only the Hub client
(`huggingface_hub.HfApi`) is replaced; the fake applies the allow patterns and copies what would be sent,
so the test sees the repositories' contents."""

from __future__ import annotations

import json
import shutil
from pathlib import Path
from typing import Any

import pytest

from talkdem.cli import main
from talkdem.leaderboard import publish_space


class FakeHub:
    """Records `create_repo` and `upload_folder` calls; `upload_folder` copies the allowed files."""

    def __init__(self, root: Path) -> None:
        self.root = root
        self.created: list[dict[str, Any]] = []

    def api(self) -> Any:
        hub = self

        class HfApi:
            def create_repo(self, repo_id: str, **kwargs: Any) -> str:
                hub.created.append({"repo_id": repo_id, **kwargs})
                return f"https://example.invalid/{repo_id}"

            def upload_folder(self, *, repo_id: str, repo_type: str, folder_path: str, **kwargs: Any) -> Any:
                from huggingface_hub.utils import filter_repo_objects

                source = Path(folder_path)
                files = sorted(p.relative_to(source).as_posix() for p in source.rglob("*") if p.is_file())
                target = hub.root / repo_type / repo_id
                for name in filter_repo_objects(files, allow_patterns=kwargs.get("allow_patterns")):
                    (target / name).parent.mkdir(parents=True, exist_ok=True)
                    shutil.copy(source / name, target / name)

                class Commit:
                    commit_url = f"https://example.invalid/{repo_type}/{repo_id}/commit/1"

                return Commit()

        return HfApi


@pytest.fixture
def hub(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> FakeHub:
    import huggingface_hub

    fake = FakeHub(tmp_path / "hub")
    monkeypatch.setattr(huggingface_hub, "HfApi", fake.api())
    return fake


def test_push_publishes_the_space_and_the_results_dataset(board: Path, hub: FakeHub, capsys) -> None:  # type: ignore[no-untyped-def]
    argv = ["push", "--leaderboard", str(board), "--repo", "org/board", "--results-repo", "org/results"]
    assert main(argv) == 0
    assert [(c["repo_id"], c["repo_type"], c.get("space_sdk")) for c in hub.created] == [
        ("org/board", "space", "static"),
        ("org/results", "dataset", None),
    ]
    space = hub.root / "space" / "org/board"
    assert (space / "README.md").read_text().startswith("---\ntitle:")
    assert (space / "index.html").is_file() and (space / "leaderboard.json").is_file()
    dataset = hub.root / "dataset" / "org/results"
    sent = sorted(p.relative_to(dataset).as_posix() for p in dataset.rglob("*.json"))
    kept = sorted(p.relative_to(board / "results").as_posix() for p in (board / "results").rglob("*.json"))
    assert sent == kept and len(sent) == 6
    assert all(json.loads((dataset / s).read_text())["config"]["model_name"] for s in sent)
    assert (dataset / "README.md").is_file()
    assert "commit/1" in capsys.readouterr().err


def test_dry_run_lists_what_would_be_sent(board: Path, hub: FakeHub, capsys) -> None:  # type: ignore[no-untyped-def]
    argv = ["push", "--leaderboard", str(board), "--repo", "o/b", "--results-repo", "o/r", "--dry-run"]
    assert main(argv) == 0
    lines = capsys.readouterr().out.splitlines()
    assert "space o/b: index.html" in lines and "space o/b: README.md" in lines
    assert sum(line.startswith("dataset o/r: ") and line.endswith(".json") for line in lines) == 6
    assert hub.created == []


def test_push_refuses_what_is_not_a_leaderboard(tmp_path: Path, hub: FakeHub, capsys) -> None:  # type: ignore[no-untyped-def]
    assert main(["push", "--leaderboard", str(tmp_path), "--repo", "o/b"]) == 2
    assert "not a leaderboard folder" in capsys.readouterr().err
    (tmp_path / "README.md").write_text("---\nsdk: gradio\n---\n")
    (tmp_path / "index.html").write_text("<html></html>")
    with pytest.raises(ValueError, match="sdk: static"):
        publish_space(tmp_path, "o/b")
    assert main(["push", "--results-repo", "o/r", "--repo", "o/b"]) == 2
    assert "--results-repo needs --leaderboard" in capsys.readouterr().err
    assert hub.created == []


def test_push_refuses_a_bad_repo_name(board: Path, hub: FakeHub) -> None:
    with pytest.raises(ValueError, match="ORG/NAME"):
        publish_space(board, "board")
