"""The dataset by Hub id: a TALK-Dem dataset repository, fetched into the Hugging Face cache.

`TALKDEM_DATA_DIR=ORG/talk-dem` (or `data_dir("ORG/talk-dem")`) makes every command read that copy: the
Parquet configs, the tasks with their scene data, the planner's worked examples. With `HF_HUB_OFFLINE=1`
only the cache is read, and a copy that is not there fails at once with one line saying so (no retries).
"""

from __future__ import annotations

import os
import re
from functools import cache
from pathlib import Path

__all__ = ["HubDatasetError", "dataset_snapshot", "is_repo_id", "names_hub_dataset", "upload", "upload_plan"]

_REPO_ID = re.compile(
    r"[A-Za-z0-9](?:[A-Za-z0-9._-]{0,94}[A-Za-z0-9])?/[A-Za-z0-9](?:[A-Za-z0-9._-]{0,94}[A-Za-z0-9])?"
)


def upload(
    folder: Path,
    repo: str,
    *,
    repo_type: str,
    allow_patterns: list[str],
    message: str,
    private: bool = False,
    space_sdk: str | None = None,
) -> str:
    """Create the Hub repository if needed and upload what `allow_patterns` selects from `folder`; returns
    the commit URL. The one path to the Hub for the dataset, the leaderboard Space and its results."""
    from huggingface_hub import HfApi

    if not is_repo_id(repo):
        raise ValueError(f"--repo must be ORG/NAME, got '{repo}'")
    api = HfApi()
    if space_sdk is None:
        api.create_repo(repo, repo_type=repo_type, private=private, exist_ok=True)
    else:
        api.create_repo(repo, repo_type=repo_type, private=private, exist_ok=True, space_sdk=space_sdk)
    commit = api.upload_folder(
        repo_id=repo,
        repo_type=repo_type,
        folder_path=str(folder),
        allow_patterns=allow_patterns,
        commit_message=message,
    )
    return str(getattr(commit, "commit_url", commit))


def upload_plan(folder: Path, allow_patterns: list[str] | tuple[str, ...]) -> list[str]:
    """The paths (relative to `folder`, sorted) that `upload` would send with these patterns: the Hub client's
    own matcher decides, so a dry run lists exactly what an upload sends."""
    from huggingface_hub.utils import filter_repo_objects  # type: ignore[attr-defined]  # re-exported, public

    files = sorted(p.relative_to(folder).as_posix() for p in Path(folder).rglob("*") if p.is_file())
    return list(filter_repo_objects(files, allow_patterns=list(allow_patterns)))


class HubDatasetError(FileNotFoundError):
    """The dataset repository could not be had (offline and not cached, unknown, unreachable)."""


def is_repo_id(text: str) -> bool:
    """`ORG/NAME` as the Hub spells repository ids."""
    return bool(_REPO_ID.fullmatch(text)) and ".." not in text


def names_hub_dataset(text: str) -> bool:
    """A data location that is a Hub id and not a folder here (a local `org/name` folder wins)."""
    return is_repo_id(text) and not Path(text).exists()


def _offline() -> bool:
    return os.environ.get("HF_HUB_OFFLINE", "").strip().lower() in ("1", "true", "yes", "on")


@cache
def dataset_snapshot(repo_id: str, revision: str | None = None) -> Path:
    """The local folder of the dataset repository `repo_id` (downloaded once, then read from the cache)."""
    from huggingface_hub import snapshot_download
    from huggingface_hub.errors import LocalEntryNotFoundError

    offline = _offline()
    try:
        folder = snapshot_download(repo_id, repo_type="dataset", revision=revision, local_files_only=offline)
    except LocalEntryNotFoundError:
        if offline:
            raise HubDatasetError(
                f"{repo_id}: not in the Hugging Face cache and HF_HUB_OFFLINE is set; fetch it once online "
                "(unset HF_HUB_OFFLINE) or point TALKDEM_DATA_DIR at a dataset folder"
            ) from None
        raise HubDatasetError(f"{repo_id}: the Hub could not be reached and the dataset is not cached") from None
    except Exception as exc:  # repository not found, gated, HTTP errors: one line, not a traceback
        raise HubDatasetError(
            f"{repo_id}: cannot fetch the dataset from the Hub ({type(exc).__name__}: {exc})"
        ) from None
    return Path(folder)
