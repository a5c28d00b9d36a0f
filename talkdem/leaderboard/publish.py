"""Publish a leaderboard folder: the folder as a static Space, its results as a dataset.

Everything goes through `huggingface_hub.HfApi` (`create_repo`, `upload_folder`); what is uploaded is
decided here, by allow patterns, so a dry run lists exactly the files a real push sends.
"""

from __future__ import annotations

from pathlib import Path

from talkdem.hub import upload, upload_plan

__all__ = [
    "RESULTS_PATTERNS",
    "SPACE_PATTERNS",
    "check_space_folder",
    "publish_results",
    "publish_space",
    "results_upload_plan",
    "space_upload_plan",
]

SPACE_PATTERNS = ("README.md", "index.html", "leaderboard.json", "results/README.md", "results/*.json")
RESULTS_PATTERNS = ("README.md", "*.json")


def _check_repo(repo: str) -> None:
    if repo.count("/") != 1 or not all(repo.split("/")):
        raise ValueError(f"--repo must be ORG/NAME, got '{repo}'")


def check_space_folder(folder: Path) -> None:
    """A clear error unless `folder` is a leaderboard folder (`talkdem leaderboard --out`)."""
    readme = folder / "README.md"
    if not readme.is_file() or not (folder / "index.html").is_file():
        raise FileNotFoundError(f"{folder}: not a leaderboard folder (run `talkdem leaderboard --out {folder}`)")
    head = readme.read_text(encoding="utf-8").split("---")
    if len(head) < 3 or "sdk: static" not in head[1]:
        raise ValueError(f"{readme}: the front matter does not declare `sdk: static`")


def space_upload_plan(folder: Path) -> list[str]:
    """Paths (relative to `folder`) a Space push uploads."""
    check_space_folder(folder)
    return upload_plan(folder, SPACE_PATTERNS)


def results_upload_plan(folder: Path) -> list[str]:
    """Paths (relative to `folder/results`) a results push uploads."""
    check_space_folder(folder)
    found = upload_plan(folder / "results", RESULTS_PATTERNS)
    if not any(p.endswith(".json") for p in found):
        raise ValueError(f"{folder / 'results'}: no results files")
    return found


def publish_space(folder: Path, repo: str, *, private: bool = False, message: str = "Update leaderboard") -> str:
    """Create the static Space if needed and upload the folder; returns the commit URL."""
    _check_repo(repo)
    space_upload_plan(folder)
    return upload(
        folder,
        repo,
        repo_type="space",
        allow_patterns=list(SPACE_PATTERNS),
        message=message,
        private=private,
        space_sdk="static",
    )


def publish_results(folder: Path, repo: str, *, private: bool = False, message: str = "Add results") -> str:
    """Create the results dataset if needed and upload `folder/results`; returns the commit URL."""
    _check_repo(repo)
    results_upload_plan(folder)
    return upload(
        folder / "results",
        repo,
        repo_type="dataset",
        allow_patterns=list(RESULTS_PATTERNS),
        message=message,
        private=private,
    )
