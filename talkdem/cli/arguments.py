"""Argument types shared by the subcommands: a bad value is refused by argparse with one line naming the
option, before any work starts (a `--limit 0` run that does nothing and exits 0 looks like a success)."""

from __future__ import annotations

import argparse
import re
from pathlib import Path

__all__ = [
    "bootstrap_count",
    "file_path",
    "folder_path",
    "hub_repo_id",
    "non_negative_int",
    "page_link",
    "positive_int",
]

# The Hub's rule for repository ids: ORG/NAME, letters, digits, '-', '_', '.', no leading/trailing '-'/'.'.
_REPO_PART = r"[A-Za-z0-9](?:[A-Za-z0-9._-]{0,94}[A-Za-z0-9])?"
_REPO_ID = re.compile(rf"{_REPO_PART}/{_REPO_PART}")


def _integer(text: str) -> int:
    try:
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a whole number") from None


def positive_int(text: str) -> int:
    """1, 2, ...: counts of tasks, steps, threads."""
    value = _integer(text)
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, got {value}")
    return value


def non_negative_int(text: str) -> int:
    """0, 1, ...: counts where 0 means 'none' (bootstrap resamples)."""
    value = _integer(text)
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be 0 or more, got {value}")
    return value


def bootstrap_count(text: str) -> int:
    """`--bootstrap`: 0 turns the intervals off (said so in the report and on the page); otherwise a count of
    resamples of at least `MIN_RESAMPLES` (fewer cannot make a 95% percentile interval)."""
    from talkdem.metrics.stats import check_resamples

    value = _integer(text)
    try:
        return check_resamples(value, "the count")
    except ValueError as error:
        raise argparse.ArgumentTypeError(str(error).removeprefix("the count ")) from None


def folder_path(text: str) -> Path:
    """An output folder: `''` is refused (as a Path it is `.`, and the command would write into the current
    folder without having been asked to)."""
    if not text.strip():
        raise argparse.ArgumentTypeError("must name a folder, got an empty string (use '.' for the current folder)")
    return Path(text)


def file_path(text: str) -> Path:
    """An output file: `''` is refused (as a Path it is `.`, the current folder, which cannot be written as a file)."""
    if not text.strip():
        raise argparse.ArgumentTypeError("must name a file, got an empty string")
    return Path(text)


def hub_repo_id(text: str) -> str:
    """`ORG/NAME` as the Hugging Face Hub accepts it."""
    if not _REPO_ID.fullmatch(text) or ".." in text or "--" in text:
        raise argparse.ArgumentTypeError(
            f"'{text}' is not a Hub repository id (ORG/NAME: letters, digits, '-', '_', '.')"
        )
    return text


def page_link(text: str) -> str:
    """A link a published page may carry: relative (`viewer/index.html`, `../viewer/`) or http(s), as a browser
    reads it (`talkdem.report.links`); never a script, nor an absolute path of this machine (it would not resolve
    anywhere else and tells where files live)."""
    from talkdem.report.links import UnsafeLinkError, safe_href

    try:
        return safe_href(text)
    except UnsafeLinkError as error:
        raise argparse.ArgumentTypeError(str(error)) from None
