"""Local execution: `--workers N` `talkdem run` processes at a time, each on one job (a run or one of its
shards), `--threads T` each; a finished run's shards are merged as soon as its last job ends."""

from __future__ import annotations

import signal
import subprocess
import sys
import time
from collections import deque
from collections.abc import Sequence
from pathlib import Path
from typing import IO

from talkdem.sweeps.book import JobBook
from talkdem.sweeps.progress import SweepProgress
from talkdem.sweeps.work import Job, work_folder

__all__ = ["run_local"]

_POLL_SECONDS = 0.5
_STOP_SECONDS = 60


def _last_line(log: Path) -> str:
    lines = [line for line in log.read_text(encoding="utf-8", errors="replace").splitlines() if line.strip()]
    return lines[-1].strip() if lines else "exited without a message"


def run_local(
    book: JobBook,
    *,
    workers: int,
    threads: int | None,
    continue_on_new_revision: bool,
    progress: SweepProgress,
    talkdem: Sequence[str] = (),
) -> None:
    """Run every pending job of `book` in up to `workers` processes; failures are recorded in the book.
    `talkdem`: how to start the `talkdem` command (default: this interpreter's `python -m talkdem`)."""
    launcher = list(talkdem) or [sys.executable, "-m", "talkdem"]
    queue = deque(book.pending())
    logs = work_folder(book.spec.out) / "logs"
    running: dict[str, tuple[Job, subprocess.Popen[bytes], Path, IO[bytes]]] = {}
    try:
        while queue or running:
            while queue and len(running) < workers:
                job = queue.popleft()
                if book.skip(job):
                    continue
                logs.mkdir(parents=True, exist_ok=True)
                log = logs / f"{job.key.replace(' ', '.').replace('/', '-of-')}.log"
                handle: IO[bytes] = log.open("wb")
                command = [*launcher, "run", *job.command(threads, continue_on_new_revision)]
                process = subprocess.Popen(command, stdout=handle, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL)
                running[job.key] = (job, process, log, handle)
            time.sleep(_POLL_SECONDS)
            for key, (job, process, log, handle) in list(running.items()):
                code = process.poll()
                if code is None:
                    continue
                del running[key]
                handle.close()
                if code == 0:
                    log.unlink()
                    book.finished(job)
                else:
                    book.failed(job, f"{_last_line(log)} (exit {code}; output in {log})")
            progress.update(*book.done())
        if logs.is_dir() and not any(logs.iterdir()):
            logs.rmdir()
    except BaseException:
        _stop([process for _, process, _, _ in running.values()])
        raise


def _stop(processes: list[subprocess.Popen[bytes]]) -> None:
    """Stop the jobs with SIGTERM, which `talkdem run` handles as Ctrl-C (each saves what it finished and
    marks its run incomplete; SIGINT would not reach a worker of a sweep started in the background, which
    inherits it ignored), then wait for them."""
    for process in processes:
        if process.poll() is None:
            process.send_signal(signal.SIGTERM)
    deadline = time.monotonic() + _STOP_SECONDS
    for process in processes:
        try:
            process.wait(timeout=max(0.0, deadline - time.monotonic()))
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()
