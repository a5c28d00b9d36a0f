"""A sweep's progress on stderr: episodes on disk of those planned, runs finished, and the rate of this sitting
(one line at a time, every few seconds: several worker processes cannot share one progress bar)."""

from __future__ import annotations

import sys
import time
from typing import TextIO

__all__ = ["SweepProgress"]


def _duration(seconds: float) -> str:
    minutes, secs = divmod(int(seconds), 60)
    hours, minutes = divmod(minutes, 60)
    return f"{hours}h{minutes:02d}m" if hours else f"{minutes}m{secs:02d}s"


class SweepProgress:
    """Counts and rate of a sweep, printed when they change, at most every `interval` seconds."""

    def __init__(
        self,
        total: int,
        done: int,
        runs: int,
        *,
        enabled: bool = True,
        interval: float = 10.0,
        stream: TextIO | None = None,
    ) -> None:
        self.total = total
        self.resumed = done
        self.runs = runs
        self.enabled = enabled
        self.interval = interval
        self.stream = stream or sys.stderr
        self._start = time.monotonic()
        self._last_print = -float("inf")
        self._last: tuple[int, int] | None = None

    def line(self, done: int, runs_done: int) -> str:
        elapsed = time.monotonic() - self._start
        ran = done - self.resumed
        parts = [f"sweep: {done}/{self.total} episodes ({self.resumed} resumed)", f"{runs_done}/{self.runs} runs done"]
        if ran > 0 and elapsed > 0:
            rate = ran / elapsed
            parts.append(f"{rate * 3600:.0f} episodes/h")
            if done < self.total:
                parts.append(f"about {_duration((self.total - done) / rate)} left")
        parts.append(f"{_duration(elapsed)} elapsed")
        return ", ".join(parts)

    def update(self, done: int, runs_done: int, *, force: bool = False) -> None:
        if not self.enabled:
            return
        now = time.monotonic()
        changed = (done, runs_done) != self._last
        if (force and (changed or self._last is None)) or (changed and now - self._last_print >= self.interval):
            print(self.line(done, runs_done), file=self.stream, flush=True)
            self._last_print = now
            self._last = (done, runs_done)
