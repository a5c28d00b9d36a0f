"""Where TALK-Dem finds its inputs and writes its outputs.

Every location has a default that works in a clone of the repository with `../shared` beside it, and an
environment variable (and, in the CLI, an option) so that a user points the package at their own ALFRED
download or dataset folder.
"""

from __future__ import annotations

import hashlib
import os
import re
from pathlib import Path

__all__ = [
    "ALFRED_DIR_ENV",
    "CACHE_DIR_ENV",
    "DATA_DIR_ENV",
    "FLOORPLANS_DIR_ENV",
    "MAX_STEM",
    "SHARED_DATA_ENV",
    "alfred_dir",
    "bundled_dir",
    "cache_dir",
    "data_dir",
    "evaluate_module_dir",
    "file_stem",
    "floorplans_dir",
    "repo_root",
    "shared_data_dir",
]

ALFRED_DIR_ENV = "TALKDEM_ALFRED_DIR"
FLOORPLANS_DIR_ENV = "TALKDEM_FLOORPLANS_DIR"
SHARED_DATA_ENV = "TALKDEM_SHARED_DATA"
DATA_DIR_ENV = "TALKDEM_DATA_DIR"
CACHE_DIR_ENV = "TALKDEM_CACHE_DIR"


def repo_root() -> Path:
    """The project checkout (the folder holding `talkdem/`, `data/`, `builders/`)."""
    return Path(__file__).resolve().parent.parent


def shared_data_dir() -> Path:
    """The read-only seed data: `$TALKDEM_SHARED_DATA`, else `../shared/data` beside the checkout."""
    override = os.environ.get(SHARED_DATA_ENV)
    return Path(override) if override else repo_root().parent / "shared" / "data"


def alfred_dir(override: str | Path | None = None) -> Path:
    """ALFRED `json_2.1.0/` folder: argument, then `$TALKDEM_ALFRED_DIR`, then the REI-Bench seed pool."""
    chosen = override or os.environ.get(ALFRED_DIR_ENV)
    return Path(chosen) if chosen else shared_data_dir() / "alfred_seed_pool" / "json_2.1.0"


def floorplans_dir(override: str | Path | None = None) -> Path:
    """Scene object lists (`FloorPlan<N>-objects.json`, `-openable.json`)."""
    chosen = override or os.environ.get(FLOORPLANS_DIR_ENV)
    return Path(chosen) if chosen else shared_data_dir() / "floorplans"


def bundled_dir() -> Path:
    """Where an installed wheel carries the dataset and the `evaluate` module (`setup.py` copies them)."""
    return Path(__file__).resolve().parent / "_bundled"


def _checkout_or_bundled(name: str, marker: str) -> Path:
    # A checkout's own folder wins (it is what the builders write); an installed wheel has only its copy.
    in_checkout = repo_root() / name
    if (in_checkout / marker).is_file():
        return in_checkout
    bundled = bundled_dir() / name
    return bundled if (bundled / marker).is_file() else in_checkout


def data_dir(override: str | Path | None = None) -> Path:
    """The generated dataset folder: argument, `$TALKDEM_DATA_DIR`, the checkout's `data/`, else the copy
    bundled in the installed wheel. A Hub id (`ORG/talk-dem`) that is not a folder here names the dataset
    repository, fetched into the Hugging Face cache (`talkdem.hub`)."""
    chosen = override or os.environ.get(DATA_DIR_ENV)
    if not chosen:
        return _checkout_or_bundled("data", "README.md")
    from talkdem.hub import dataset_snapshot, names_hub_dataset

    return dataset_snapshot(str(chosen)) if names_hub_dataset(str(chosen)) else Path(chosen)


def evaluate_module_dir() -> Path:
    """The `evaluate` metric module's folder, for `evaluate.load(str(evaluate_module_dir()))`."""
    return _checkout_or_bundled("evaluate_talkdem", "evaluate_talkdem.py")


def cache_dir() -> Path:
    """Derived artefacts worth keeping between runs (converted models, embeddings): `$TALKDEM_CACHE_DIR`,
    else `~/.cache/talkdem`."""
    override = os.environ.get(CACHE_DIR_ENV)
    return Path(override) if override else Path.home() / ".cache" / "talkdem"


MAX_STEM = 100
"""The longest file-name stem `file_stem` gives: file systems allow 255 bytes per name, and callers add to a
stem (`heatmap_`, `.json`, a hash to keep two stems apart)."""


def file_stem(text: str, fallback: str) -> str:
    """A file-name-safe stem of `text` (a model or run name): letters, digits, `.`, `_` and `-`, every other run
    of characters as `_`, no leading or trailing `_` or `.` (`fallback` when nothing is left), and at most
    `MAX_STEM` characters. A longer stem keeps its start and ends with 8 hex digits of the whole text's
    sha256, so long names that share a start still get different stems."""
    stem = re.sub(r"[^A-Za-z0-9._-]+", "_", text).strip("_.") or fallback
    if len(stem) > MAX_STEM:
        digest = hashlib.sha256(text.encode("utf-8", "surrogatepass")).hexdigest()[:8]
        stem = f"{stem[: MAX_STEM - 9].rstrip('_.-')}-{digest}"
    return stem
