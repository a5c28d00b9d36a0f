"""Run `talkdem run` in this process with the scripted test model registered as backend `scripted`.

Used by the resume test, which kills this process with SIGKILL mid-run. Argument 1: seconds to sleep per
scoring call (to give the test time to kill it), the rest: `talkdem run` arguments.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent.parent / "planner"))

from scripted_lm import ScriptedLM

from talkdem.cli import main
from talkdem.llm.interface import registry

DELAY = float(sys.argv[1])


class SlowScripted(ScriptedLM):
    def __init__(self, model: str, **_: object) -> None:
        super().__init__(["find an apple", "pick up the apple", "done"])

    def loglikelihood(self, requests):  # type: ignore[no-untyped-def]
        time.sleep(DELAY)
        return super().loglikelihood(requests)


registry.BACKENDS.register("scripted", SlowScripted)
sys.modules[__name__] = sys.modules["__main__"]
sys.exit(main(sys.argv[2:]))
