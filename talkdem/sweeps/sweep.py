"""`run_sweep`: prepare every run of a spec (split, resume, skip what is settled), run the jobs locally or on
Ray, merge each run as its last job ends; `describe`: the expansion, for `--dry-run` (reads, writes nothing)."""

from __future__ import annotations

import os
import shlex
import sys
from collections.abc import Sequence
from dataclasses import dataclass

from talkdem.runs.store import run_lock
from talkdem.sweeps.book import JobBook
from talkdem.sweeps.progress import SweepProgress
from talkdem.sweeps.spec import SweepRun, SweepSpec
from talkdem.sweeps.work import done_episodes, prepare, work_folder

__all__ = ["SweepResult", "describe", "run_sweep"]


@dataclass(frozen=True)
class SweepResult:
    complete: tuple[str, ...]
    """Run directories complete at the end."""
    failures: tuple[str, ...]
    """One line per job or merge that failed (its run resumes on the next sweep)."""
    episodes: int
    resumed: int
    model_loads: dict[str, tuple[int, int]]
    """Ray: per model of the spec, (models loaded by its actors in all, jobs they ran): one load per actor."""


def default_threads(workers: int) -> int:
    """The CPUs of this machine shared among the workers (at least one thread each)."""
    return max(1, (os.cpu_count() or 1) // workers)


def run_sweep(
    spec: SweepSpec,
    *,
    workers: int | None = None,
    threads: int | None = None,
    shards: int | None = None,
    ray: str | None = None,
    continue_on_new_revision: bool = False,
    progress: bool = True,
    talkdem: Sequence[str] = (),
) -> SweepResult:
    """Run the sweep `spec` to the end (resuming what is on disk); `continue_on_new_revision`: every run may resume
    a run directory started on another code revision (as `talkdem run --continue-on-new-revision`);
    `talkdem`: how local workers start the command (default `python -m talkdem` of this interpreter)."""
    connected = False
    if ray is not None:
        from talkdem.sweeps.ray_cluster import connect

        connected = connect(ray)  # first: the default worker count is the cluster's; a wrong address fails now
    try:
        return _run(spec, workers, threads, shards, ray, continue_on_new_revision, progress, talkdem)
    finally:
        if connected:
            import ray as ray_module

            ray_module.shutdown()


def _run(
    spec: SweepSpec,
    workers: int | None,
    threads: int | None,
    shards: int | None,
    ray: str | None,
    continue_on_new_revision: bool,
    progress: bool,
    talkdem: Sequence[str],
) -> SweepResult:
    local_workers = workers or 1
    # Local workers share this machine's CPUs; a Ray actor reserves as many CPUs as it has threads.
    threads = threads or (default_threads(local_workers) if ray is None else 1)
    spec.out.mkdir(parents=True, exist_ok=True)
    with run_lock(spec.out):  # one sweep at a time on an output root

        def shard_count(run: SweepRun) -> int:
            if shards or spec.shards:
                return shards or spec.shards or 1
            if ray is not None and workers is None:
                from talkdem.sweeps.ray_cluster import default_workers

                return default_workers(run, threads or 1)
            return local_workers

        works = [prepare(spec, run, shard_count(run)) for run in spec.runs]
        for work in works:
            for note in work.notes:
                print(f"sweep: {note}", file=sys.stderr)
        book = JobBook(spec, works)
        book.start()
        total = sum(len(w.run.episode_ids) for w in works)
        done, runs_done = book.done()
        meter = SweepProgress(total, done, len(works), enabled=progress)
        meter.update(done, runs_done, force=True)
        loads: dict[str, tuple[int, int]] = {}
        if ray is None:
            from talkdem.sweeps.local import run_local

            run_local(
                book,
                workers=local_workers,
                threads=threads,
                continue_on_new_revision=continue_on_new_revision,
                progress=meter,
                talkdem=talkdem,
            )
        else:
            from talkdem.sweeps.ray_cluster import run_ray

            loads = run_ray(
                book,
                address=ray,
                workers=workers,
                threads=threads,
                continue_on_new_revision=continue_on_new_revision,
                progress=meter,
            )
        final, _ = book.done()
        meter.update(*book.done(), force=True)
        complete = tuple(str(w.run.run_dir) for w in works if w.merged)
        folder = work_folder(spec.out)
        if folder.is_dir() and not any(folder.iterdir()):
            folder.rmdir()
        return SweepResult(complete, tuple(book.failures), final, done, loads)


def describe(spec: SweepSpec, *, workers: int | None, threads: int | None, shards: int | None, ray: bool) -> str:
    """The expansion of `spec`: each run directory, its episodes (and how many are on disk), its shards and the
    `talkdem run` command it amounts to."""
    total = sum(len(r.episode_ids) for r in spec.runs)
    lines = [f"{spec.path}: {len(spec.runs)} runs, {total} episodes, into {spec.out}"]
    count = shards or spec.shards or (workers if ray else workers or 1)
    for run in spec.runs:
        on_disk = done_episodes(run.run_dir) + sum(
            done_episodes(p) for p in (work_folder(spec.out) / run.name).glob("shard-*-of-*")
        )
        n = len(run.episode_ids)
        split = f"{min(count, n)} shard(s)" if count else "one shard per Ray actor"
        lines.append(
            f"  {run.run_dir}: {run.backend} {run.model}, {run.strategy}, {n} episodes "
            f"({min(on_disk, n)} on disk), {split}"
        )
        thread_count = threads or (1 if ray else default_threads(workers or 1))
        lines.append(f"    talkdem run {shlex.join(run.command(out=run.run_dir, threads=thread_count))}")
    return "\n".join(lines)
