"""Dataset fixtures: one reference build per session, in a temporary folder."""

from __future__ import annotations

import pytest

from builders.build import BuildResult, build


@pytest.fixture(scope="session")
def reference_build(tmp_path_factory: pytest.TempPathFactory) -> BuildResult:
    """An uninterrupted build with the default generator and seed."""
    root = tmp_path_factory.mktemp("reference")
    return build(root / "data", checkpoint=root / "checkpoint.jsonl", progress=False)
