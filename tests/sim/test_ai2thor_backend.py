"""The optional AI2-THOR backend: pure translation tested here; the controller itself needs a build."""

from __future__ import annotations

import importlib.util

import pytest
from helpers import first_task

from talkdem.sim import AI2ThorExecutor, AI2ThorUnavailableError, ThorAction, translate_skill
from talkdem.sim.ai2thor_backend import find_build
from talkdem.skills import vocabulary


def test_translation_follows_lotabench() -> None:
    assert translate_skill("find an apple") == (ThorAction("TeleportFull", "Apple", {"standing": True}),)
    assert translate_skill("put down the apple") == (ThorAction("PutObject", "", {"forceAction": True}),)
    assert translate_skill("Turn on the Microwave.") == (
        ThorAction("ToggleObjectOn", "Microwave", {"forceAction": True}),
    )
    assert translate_skill("slice the bread")[0].action == "SliceObject"
    assert translate_skill("done") == (ThorAction("Done"),)
    assert translate_skill("fly away") == ()


def test_every_skill_translates() -> None:
    assert all(translate_skill(skill) for skill in vocabulary())


def test_missing_build_path_is_named(tmp_path: object) -> None:
    with pytest.raises(AI2ThorUnavailableError, match="local_executable_path"):
        find_build("/nonexistent/thor-build")


@pytest.mark.skipif(importlib.util.find_spec("ai2thor") is not None, reason="ai2thor is installed")
def test_without_ai2thor_the_error_says_what_to_install() -> None:
    with pytest.raises(AI2ThorUnavailableError, match="ai2thor"):
        AI2ThorExecutor().run(first_task("pick_and_place_simple"), ["done"])
