"""Stopping a command with SIGTERM as cleanly as with Ctrl-C.

Every long command (`run`, `sweep`, `build`) already saves what it finished and marks its run `incomplete`
when interrupted (KeyboardInterrupt). A job stopped by `kill`, a scheduler or a sweep stopping its workers
sends SIGTERM, whose default action ends the process on the spot: the header would still say `running` and
a sweep's workers would be left running. And a job started in the background (`nohup ... &`) inherits
SIGINT ignored, so Ctrl-C's signal does not reach it at all. Here SIGTERM raises `Terminated`, a
KeyboardInterrupt, so the same clean-up runs. The first signal disarms both handlers, so a second signal
(Ctrl-C delivered to the whole process group, then the sweep's own SIGTERM to its workers) cannot break
into that clean-up.
"""

from __future__ import annotations

import signal
from collections.abc import Iterator
from contextlib import contextmanager
from types import FrameType

__all__ = ["TERMINATED_EXIT", "Terminated", "stop_on_signals"]

TERMINATED_EXIT = 128 + signal.SIGTERM
"""The shell's exit status of a process ended by SIGTERM."""


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised where the process was, as Ctrl-C's KeyboardInterrupt is."""


@contextmanager
def stop_on_signals() -> Iterator[None]:
    """Within the block, SIGTERM raises `Terminated` and SIGINT KeyboardInterrupt, each once; SIGINT stays
    ignored where the process was started with it ignored. Outside the main thread this does nothing (Python
    delivers signals to the main thread only)."""
    handled = [signal.SIGTERM]
    if signal.getsignal(signal.SIGINT) is not signal.SIG_IGN:
        handled.append(signal.SIGINT)

    def stop(signum: int, frame: FrameType | None) -> None:
        for number in handled:
            signal.signal(number, signal.SIG_IGN)
        raise Terminated() if signum == signal.SIGTERM else KeyboardInterrupt()

    try:
        previous = {number: signal.signal(number, stop) for number in handled}
    except ValueError:  # not the main thread
        yield
        return
    try:
        yield
    finally:
        for number, handler in previous.items():
            signal.signal(number, handler)
