"""Shared fixtures: the real seed pool from ../shared/data and the stored task sets."""

from __future__ import annotations

import pytest

from talkdem.seeds import SeedTask, load_seed_pool


@pytest.fixture(scope="session")
def seed_pool() -> list[SeedTask]:
    return load_seed_pool()
