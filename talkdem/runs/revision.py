"""The code revision recorded in every result file."""

from __future__ import annotations

import subprocess
from functools import cache

from talkdem import __version__
from talkdem.paths import repo_root

__all__ = ["code_revision"]


@cache
def code_revision() -> str:
    """`<git commit>` (`-dirty` when the checkout has uncommitted changes), else the package version."""
    try:
        commit = subprocess.run(
            ["git", "rev-parse", "HEAD"], cwd=repo_root(), capture_output=True, text=True, check=True, timeout=10
        ).stdout.strip()
        dirty = subprocess.run(
            ["git", "status", "--porcelain", "--untracked-files=no"],
            cwd=repo_root(),
            capture_output=True,
            text=True,
            check=True,
            timeout=10,
        ).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return f"talkdem-{__version__}"
    return f"{commit}-dirty" if dirty else commit
