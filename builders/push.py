"""Publish the dataset folder to the Hugging Face Hub (`talkdem push --repo ORG/NAME`)."""

from __future__ import annotations

from pathlib import Path

__all__ = ["ALLOW_PATTERNS", "push", "upload_plan"]

ALLOW_PATTERNS = (
    "README.md",
    "*/*.parquet",
    "build_stats.json",
    "markers.json",
    "markers.md",
    "sample.html",
    "tasks/*.jsonl",
    "prompts/*.jsonl",
    "selection/*",
)
"""What a dataset repository holds: the card (with its YAML configs), the Parquet files and the reports, and
what scoring a Hub copy needs beyond the viewer's tables: the tasks with their scene data (`tasks/*.jsonl`,
read by the simulator), the planner's worked examples and the selection report. `TALKDEM_DATA_DIR=ORG/NAME`
then runs every command on the Hub copy."""


def upload_plan(folder: Path) -> list[str]:
    """The paths (relative to `folder`) that `push` uploads, in the order `upload_folder` sees them."""
    from talkdem.hub import upload_plan as plan

    folder = Path(folder)
    if not (folder / "README.md").is_file():
        raise FileNotFoundError(f"{folder}: no README.md card (run `talkdem build` first)")
    return plan(folder, ALLOW_PATTERNS)


def push(folder: Path, repo: str, *, private: bool = False, message: str = "Upload TALK-Dem") -> str:
    """Create the dataset repository if needed and upload the planned files; returns the commit URL."""
    from talkdem.hub import upload

    upload_plan(folder)  # fails early on a folder without a card
    return upload(
        folder, repo, repo_type="dataset", allow_patterns=list(ALLOW_PATTERNS), message=message, private=private
    )
