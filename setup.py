"""Packaging hook: the wheel carries the dataset and the `evaluate` module, so an installed package works
outside the repository (`talkdem tasks`, `simulate`, `score`, `report`, `talk_dem.load`).

`data/` and `evaluate_talkdem/` stay top-level folders in the repository (the design card names them, and
`datasets` / `evaluate` load them from there); a wheel build copies them into `talkdem/_bundled/`, where
`talkdem.paths` looks when no checkout is around. Everything else is declared in pyproject.toml.
"""

from __future__ import annotations

import shutil
from pathlib import Path

from setuptools import setup
from setuptools.command.build_py import build_py

ROOT = Path(__file__).resolve().parent
BUNDLED = ("data", "evaluate_talkdem")


class BuildWithBundledData(build_py):  # type: ignore[misc]
    def run(self) -> None:
        super().run()
        if getattr(self, "editable_mode", False):
            return  # an editable install reads the checkout's own folders
        target = Path(self.build_lib) / "talkdem" / "_bundled"
        for name in BUNDLED:
            shutil.rmtree(target / name, ignore_errors=True)
            shutil.copytree(ROOT / name, target / name, ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))


setup(cmdclass={"build_py": BuildWithBundledData})
