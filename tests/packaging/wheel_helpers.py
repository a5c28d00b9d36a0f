"""Building the wheel as a user would, from a copy of the project's files (so the checkout gets no build/)."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

from talkdem.paths import repo_root

PIP = [sys.executable, "-m", "pip", "--disable-pip-version-check", "--quiet"]


def project_files() -> list[str]:
    listed = subprocess.run(
        ["git", "ls-files", "--cached", "--others", "--exclude-standard"],
        cwd=repo_root(),
        capture_output=True,
        text=True,
        check=True,
    ).stdout.splitlines()
    return [name for name in listed if (repo_root() / name).is_file()]


def build_wheel(root: Path) -> Path:
    """The wheel built from a copy of the project's files under `root/source`, in `root/dist`."""
    source = root / "source"
    for name in project_files():
        (source / name).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(repo_root() / name, source / name)
    subprocess.run(
        [*PIP, "wheel", "--no-deps", "--no-build-isolation", "-w", str(root / "dist"), str(source)], check=True
    )
    (wheel,) = (root / "dist").glob("talkdem-*.whl")
    return wheel
