"""Ray execution (`talkdem sweep --ray auto|ADDRESS`): each model's jobs (its runs, or their shards) are Ray
tasks of a pool of actors (`ShardWorker`), one model loaded per actor; served models are reached by their URLs
from wherever the actor runs. Ray places the actors and tasks (the pool hands the next job to the next free
actor: `ray.util.ActorPool`); nothing here schedules. Results come back to the driver, which writes them into
the sweep's folders and merges as the local executor does, so a finished run is the same either way.

Ray is the optional extra `ray`, imported only here and only when asked for.
"""

from __future__ import annotations

import math
import os
import socket
from pathlib import Path
from typing import Any

from talkdem.files import replace_file
from talkdem.runs.store import HEADER_FILE, run_lock
from talkdem.sweeps.actor import EPISODE_FILES, RUN_FILES, ShardWorker
from talkdem.sweeps.book import JobBook
from talkdem.sweeps.progress import SweepProgress
from talkdem.sweeps.spec import SweepRun
from talkdem.sweeps.work import Job

__all__ = ["actor_resources", "connect", "default_workers", "run_ray"]

# The extra's own requirement (pyproject.toml; a test keeps the two together), and the checkout and wheel forms:
# TALK-Dem is not on PyPI, so `pip install 'talkdem[ray]'` finds nothing.
_MISSING = (
    "Ray is not installed (the optional extra `ray`): `pip install 'ray[default]==2.60.0'`, or from a checkout "
    "`pip install -e '.[ray]'`, or with the wheel `pip install 'PATH/TO/talkdem-VERSION-py3-none-any.whl[ray]'`; "
    "every node of the cluster needs the same Ray version"
)
_POLL_SECONDS = 5.0
_LISTENING_SECONDS = 5.0
"""How long the check that something listens at `--ray HOST:PORT` waits: Ray's own connection retries for
minutes before it gives up on an address where nothing listens."""
_CLIENT_PORT = 10001
"""The port of `ray://HOST` without one (Ray Client's default)."""


def _ray() -> Any:
    try:
        import ray
    except ImportError:
        raise ImportError(_MISSING) from None
    return ray


def connect(address: str) -> bool:
    """Connect this process to the Ray cluster at `address` (`auto`: the one `ray start` left running here or
    `RAY_ADDRESS` names; `HOST:PORT`; `ray://HOST:PORT`; `local`: a new one for this process alone). True when
    this call connected (and should disconnect); an existing connection is used as it is. An address where
    nothing listens is refused at once (`ValueError` naming it), not after Ray's minutes of retries."""
    endpoint = _endpoint(address)
    if endpoint is not None:
        _check_listening(*endpoint)
    ray = _ray()
    if ray.is_initialized():
        return False
    try:
        ray.init(address=address, logging_level="ERROR", configure_logging=True)
    except (ConnectionError, RuntimeError, ValueError) as error:
        raise ValueError(f"--ray {address}: cannot connect to a Ray cluster ({str(error).splitlines()[0]})") from None
    return True


def _endpoint(address: str) -> tuple[str, str, int] | None:
    """(the address as the user named it, host, port) that `address` connects to, or None where Ray finds it
    (`auto` without `RAY_ADDRESS`: the cluster `ray start` left running on this machine; `local`; another
    client scheme). A malformed one is a `ValueError` naming it."""
    named = address
    if address == "auto":
        address = os.environ.get("RAY_ADDRESS", "").strip()
        if not address or address in ("auto", "local"):
            return None
        named = f"auto (RAY_ADDRESS={address})"
    if address == "local":
        return None
    scheme, separator, rest = address.partition("://")
    if separator and scheme != "ray":
        return None  # a client scheme of a Ray plugin: only it knows where it connects
    target = rest if separator else address
    if target.startswith("["):  # [IPv6] or [IPv6]:PORT
        host, _, after = target[1:].partition("]")
        colon, port = after[:1], after[1:]
    else:
        host, colon, port = target.rpartition(":")
        host, port = (host, port) if colon else (target, "")
    if not colon and separator:  # ray://HOST: Ray Client's default port
        port = str(_CLIENT_PORT)
    if not host or not port.isdigit() or not 0 < int(port) < 65536:
        raise ValueError(f"--ray {named}: expected auto, HOST:PORT or ray://HOST:PORT")
    return named, host, int(port)


def _check_listening(address: str, host: str, port: int) -> None:
    try:
        with socket.create_connection((host, port), timeout=_LISTENING_SECONDS):
            pass
    except OSError as error:
        timed_out = isinstance(error, TimeoutError)
        reason = f"no answer in {_LISTENING_SECONDS:g} s" if timed_out else (error.strerror or str(error) or "refused")
        where = f"[{host}]:{port}" if ":" in host else f"{host}:{port}"
        raise ValueError(
            f"--ray {address}: no Ray cluster at {where} ({reason}); "
            "start one there (`ray start --head`) or give the address it printed"
        ) from None


def actor_resources(run: SweepRun, threads: int) -> dict[str, float]:
    """What one actor of `run`'s model reserves: the spec's `ray:` settings, else `threads` CPUs for a model
    computed in the actor (hf, llamacpp) and one CPU for a served one (it waits on its servers)."""
    resources = dict(run.resources)
    resources.setdefault("num_cpus", float(threads if run.local_model else 1))
    return resources


def default_workers(run: SweepRun, threads: int) -> int:
    """How many actors of `run`'s model the connected cluster holds at once (at least one)."""
    resources = actor_resources(run, threads)
    available = _ray().cluster_resources()
    fits = [
        available.get(kind, 0.0) / amount
        for kind, amount in (("CPU", resources.get("num_cpus", 1.0)), ("GPU", resources.get("num_gpus", 0.0)))
        if amount > 0
    ]
    return max(1, math.floor(min(fits))) if fits else 1


def _seed(target: Path) -> dict[str, bytes]:
    return {name: (target / name).read_bytes() for name in RUN_FILES if (target / name).is_file()}


def _write_back(target: Path, files: dict[str, bytes]) -> None:
    """The job's run directory as the actor left it, written atomically file by file (episodes first: a header
    saying more than the episodes would be the only way to lose one). Episodes that come back in the other
    form than they went (a packed run the job unpacked to append) replace the old form, never sit beside it."""
    if not files:
        return
    with run_lock(target):
        for name in EPISODE_FILES:
            if name in files:
                replace_file(target / name, files[name])
        if any(name in files for name in EPISODE_FILES):
            for name in EPISODE_FILES:
                if name not in files:
                    (target / name).unlink(missing_ok=True)
        if HEADER_FILE in files:
            replace_file(target / HEADER_FILE, files[HEADER_FILE])


def run_ray(
    book: JobBook,
    *,
    address: str,
    workers: int | None,
    threads: int,
    continue_on_new_revision: bool,
    progress: SweepProgress,
) -> dict[str, tuple[int, int]]:
    """Run every pending job of `book` on the Ray cluster at `address`; returns, per model, the models its
    actors loaded in all and the jobs they ran (one load per actor, however many jobs)."""
    ray = _ray()
    from ray.util import ActorPool

    connected = connect(address)
    loads: dict[str, tuple[int, int]] = {}
    try:
        by_model: dict[int, list[Job]] = {}
        for job in book.pending():
            by_model.setdefault(job.run.model_index, []).append(job)
        for jobs in by_model.values():  # one model at a time: its actors hold the cluster's share for it
            resources = actor_resources(jobs[0].run, threads)
            count = max(1, min(workers or default_workers(jobs[0].run, threads), len(jobs)))
            actor = ray.remote(ShardWorker).options(max_concurrency=2, max_restarts=1, max_task_retries=1, **resources)
            actors = [actor.remote() for _ in range(count)]
            try:
                done = _drain(ray, ActorPool(actors), actors, book, jobs, threads, continue_on_new_revision, progress)
                loads[jobs[0].run.model] = (done, len(jobs))
            finally:
                for handle in actors:
                    ray.kill(handle)
    finally:
        if connected:
            ray.shutdown()
    return loads


def _drain(
    ray: Any,
    pool: Any,
    actors: list[Any],
    book: JobBook,
    jobs: list[Job],
    threads: int,
    continue_on_new_revision: bool,
    progress: SweepProgress,
) -> int:
    by_key = {job.key: job for job in jobs}
    for job in jobs:
        # The seed is read when an actor takes the job (ActorPool calls this then), not when it is queued.
        pool.submit(
            lambda a, j: a.run_job.remote(
                j.key, j.config(threads, continue_on_new_revision, out=False), _seed(j.target)
            ),
            job,
        )
    answered: set[str] = set()
    live: dict[str, int] = {}
    while pool.has_next():
        try:
            key, files, error = pool.get_next_unordered(timeout=_POLL_SECONDS)
        except TimeoutError:
            for report in ray.get([a.progress.remote() for a in actors]):
                if report is not None:
                    live[report[0]] = report[1]
            progress.update(*book.done(live))
            continue
        except ray.exceptions.RayError as failure:
            # An actor died past its restarts: its job is the one with no answer (named below).
            book.failures.append(f"a Ray actor failed: {str(failure).splitlines()[0]}")
            continue
        job = by_key[key]
        answered.add(key)
        live.pop(key, None)
        _write_back(job.target, files)
        if error:
            book.failed(job, error)
        else:
            book.finished(job)
        progress.update(*book.done(live))
    for key, job in by_key.items():
        if key not in answered:
            book.failed(job, "no answer from its Ray actor (it died); run the sweep again to resume")
    try:
        return sum(ray.get([a.model_loads.remote() for a in actors]))
    except ray.exceptions.RayError:  # an actor that died holds no count
        return -1
