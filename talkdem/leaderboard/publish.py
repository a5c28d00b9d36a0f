"""Publish a leaderboard folder: the folder as a static Space, its results as a dataset.

Everything goes through `huggingface_hub.HfApi` (`create_repo`, `upload_folder`); what is uploaded is
decided here, so a dry run lists exactly the files a real push sends. A file is sent only if the allow
patterns select it and, for JSON, it passes the results schema check (`talkdem.leaderboard.validate`): a
stray `creds.json` in `results/` or a hand-edited record is skipped and named, never uploaded. Only the
selected files are copied into a staging folder, and that folder is what `upload_folder` sees.
"""

from __future__ import annotations

import shutil
import tempfile
from pathlib import Path

from talkdem.hub import upload, upload_plan
from talkdem.leaderboard.validate import ResultsFileError, load_results_file, validate_record

__all__ = [
    "RESULTS_PATTERNS",
    "SPACE_PATTERNS",
    "check_space_folder",
    "not_uploaded",
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


def _check_board(folder: Path) -> None:
    """`leaderboard.json` must be a list of valid records: the page and the card were rendered from it."""
    import json

    board = folder / "leaderboard.json"
    try:
        records = json.loads(board.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise ResultsFileError(f"{board}: not a leaderboard file ({exc})") from None
    if not isinstance(records, list):
        raise ResultsFileError(f"{board}: expected a list of results records")
    for i, record in enumerate(records):
        validate_record(record, f"{board} [record {i}]")


def _split(base: Path, patterns: tuple[str, ...], results_under: str) -> tuple[list[str], list[tuple[str, str]]]:
    """(paths to send, (path, why) not sent), relative to `base`. JSON files under `results_under` must
    be valid results records."""
    selected = set(upload_plan(base, patterns))
    send, skipped = [], []
    for path in sorted(p.relative_to(base).as_posix() for p in base.rglob("*") if p.is_file()):
        if path not in selected:
            skipped.append((path, "not a leaderboard file"))
        elif path.endswith(".json") and path.startswith(results_under) and path != "leaderboard.json":
            try:
                load_results_file(base / path, path)
            except ResultsFileError as exc:
                skipped.append((path, str(exc).removeprefix(f"{path}: ")))
            else:
                send.append(path)
        else:
            send.append(path)
    return send, skipped


def space_upload_plan(folder: Path) -> list[str]:
    """Paths (relative to `folder`) a Space push uploads: the allowed files, results files only if valid."""
    check_space_folder(folder)
    _check_board(folder)
    return _split(folder, SPACE_PATTERNS, "results/")[0]


def results_upload_plan(folder: Path) -> list[str]:
    """Paths (relative to `folder/results`) a results push uploads: the card and the valid results files."""
    check_space_folder(folder)
    found = _split(folder / "results", RESULTS_PATTERNS, "")[0]
    if not any(p.endswith(".json") for p in found):
        raise ValueError(f"{folder / 'results'}: no valid results files")
    return found


def not_uploaded(folder: Path, *, results: bool = False) -> list[tuple[str, str]]:
    """(path, why) for each file under `folder` (`folder/results` with `results`) a push leaves out."""
    if results:
        return _split(folder / "results", RESULTS_PATTERNS, "")[1]
    return _split(folder, SPACE_PATTERNS, "results/")[1]


def _upload_only(
    base: Path,
    paths: list[str],
    repo: str,
    *,
    repo_type: str,
    allow_patterns: list[str],
    message: str,
    private: bool,
    space_sdk: str | None = None,
) -> str:
    """Upload exactly `paths` (relative to `base`): they are copied into a staging folder first, so no
    pattern can match a file that was not checked."""
    with tempfile.TemporaryDirectory(prefix="talkdem-push-") as staging:
        for path in paths:
            target = Path(staging) / path
            target.parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(base / path, target)
        return upload(
            Path(staging),
            repo,
            repo_type=repo_type,
            allow_patterns=allow_patterns,
            message=message,
            private=private,
            space_sdk=space_sdk,
        )


def publish_space(folder: Path, repo: str, *, private: bool = False, message: str = "Update leaderboard") -> str:
    """Create the static Space if needed and upload the folder; returns the commit URL."""
    _check_repo(repo)
    return _upload_only(
        folder,
        space_upload_plan(folder),
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
    return _upload_only(
        folder / "results",
        results_upload_plan(folder),
        repo,
        repo_type="dataset",
        allow_patterns=list(RESULTS_PATTERNS),
        message=message,
        private=private,
    )
