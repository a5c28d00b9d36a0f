"""The scripted test model as backend `scripted` (this process: the spec's checks; workers start
tests/runs/run_scripted.py, which registers it there), for the tests of the sweep's own logic."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent.parent / "planner"))

from scripted_lm import ScriptedLM

from talkdem.llm.interface import registry


class _Scripted(ScriptedLM):
    def __init__(self, model: str, **_: object) -> None:
        super().__init__(["find an apple", "pick up the apple", "done"])


if "scripted" not in registry.BACKENDS:
    registry.BACKENDS.register("scripted", _Scripted)
