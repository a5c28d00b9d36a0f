"""What is left of a sweep's run, as jobs for an executor, and the merge that turns finished shards into the run
directory: the sharding, the split and the merge are `talkdem.runs.shards`' (`--shard I/N`, `split_run`,
`merge_runs`), nothing else.

    OUT/NAME/                        the run directory (an ordinary `talkdem run` one; written by the merge)
    OUT/.sweep/NAME/shard-I-of-N/    the shards while the run is under way (removed once merged)
    OUT/.sweep/logs/                 the output of a failed local job

One shard: the job runs into `OUT/NAME` itself, exactly as `talkdem run --out OUT/NAME` does. Several: each job
is `talkdem run --shard I/N --out OUT/.sweep/NAME/shard-I-of-N`; a run directory already there (a serial run, or
a sweep with fewer tasks) is split first with `split_run`, so its finished episodes seed the shards and are
never run again. A shard folder left by an interrupted sweep is resumed as it is (its shard count wins over
`--shards`, which says so). A run or shard is *settled* (its job skipped, no model loaded) when its header says
complete, every episode of its selection is on disk, and its recorded settings are the spec's; anything else
goes through `talkdem run`, whose resume check refuses a different run.
"""

from __future__ import annotations

import gzip
import os
import re
import shutil
import warnings
import zlib
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from talkdem.runs.config import RunConfig
from talkdem.runs.episode_files import MAX_EPISODES_BYTES
from talkdem.runs.records import RunHeader
from talkdem.runs.shards import Shard, merge_runs, shard_folder, shard_of, split_run
from talkdem.runs.store import EPISODES_FILE, HEADER_FILE, PACKED_EPISODES_FILE, read_episodes, read_header, run_lock
from talkdem.sweeps.spec import SweepRun, SweepSpec

__all__ = [
    "WORK_FOLDER",
    "Job",
    "RunWork",
    "done_episodes",
    "finish",
    "prepare",
    "wanted_header",
    "work_folder",
]

WORK_FOLDER = ".sweep"
_SHARD_NAME = re.compile(r"shard-(\d+)-of-(\d+)")


def work_folder(out: Path) -> Path:
    return out / WORK_FOLDER


@dataclass(frozen=True)
class Job:
    """One `talkdem run` of a sweep: a whole run, or one shard of it."""

    run: SweepRun
    target: Path
    """Its run directory (the run's own, or a shard folder)."""
    shard: Shard | None
    episode_ids: tuple[str, ...]

    @property
    def key(self) -> str:
        return f"{self.run.name} {self.shard}" if self.shard else self.run.name

    def config(self, threads: int | None, continue_on_new_revision: bool = False, *, out: bool = True) -> RunConfig:
        """The job's run (`out` False: without its folder, which the caller gives)."""
        return self.run.job(
            out=self.target if out else None,
            threads=threads,
            shard=str(self.shard) if self.shard else None,
            continue_on_new_revision=continue_on_new_revision,
        )

    def command(self, threads: int | None, continue_on_new_revision: bool = False) -> list[str]:
        """`talkdem run` arguments of the job (for a worker process)."""
        return self.config(threads, continue_on_new_revision).arguments()


@dataclass
class RunWork:
    """A run of the sweep: every job it consists of, and those still to run."""

    run: SweepRun
    jobs: list[Job]
    pending: list[Job]
    merged: bool = False
    notes: list[str] = field(default_factory=list)

    @property
    def sharded(self) -> bool:
        return self.jobs[0].shard is not None


def done_episodes(target: Path) -> int:
    """Episodes on disk in a run directory (finished lines; cheap enough to poll). A poll never fails on the
    moment a pack or unpack holds both files: the plain one is counted then."""
    plain, packed = target / EPISODES_FILE, target / PACKED_EPISODES_FILE
    try:
        with plain.open("rb") if plain.is_file() else gzip.open(packed, "rb") as handle:
            lines = read = 0
            # Counting stops where reading the run would refuse the file, so a packed bomb costs a poll at
            # most MAX_EPISODES_BYTES of inflating (reading the run then says what is wrong).
            for block in iter(lambda: handle.read(1 << 20), b""):
                lines, read = lines + block.count(b"\n"), read + len(block)
                if read > MAX_EPISODES_BYTES:
                    break
            return lines
    except FileNotFoundError:
        return 0
    except (OSError, EOFError, zlib.error):  # a damaged packed file: reading the run says what is wrong
        return 0


def _has_run(folder: Path) -> bool:
    if (folder / HEADER_FILE).is_file():
        return True
    if folder.is_dir() and any(folder.iterdir()):
        raise ValueError(f"{folder}: holds files but no run header; move them away or choose another out")
    return False


def _existing_shards(folder: Path) -> int | None:
    """The shard count of the shard folders under `folder`, or None when there are none.

    Some of a split's folders may be missing: a shard's folder is made when its job starts, so a sweep with
    fewer workers than shards that stops early leaves only the shards it reached (their jobs start afresh)."""
    if not folder.is_dir():
        return None
    found = [m for p in folder.iterdir() if p.is_dir() and (m := _SHARD_NAME.fullmatch(p.name))]
    if not found:
        return None
    counts = {int(m.group(2)) for m in found}
    indexes = {int(m.group(1)) for m in found}
    (count,) = counts if len(counts) == 1 else (0,)
    if not count or not indexes <= set(range(1, count + 1)):
        raise ValueError(f"{folder}: holds shard folders of different splits; merge or remove them")
    return count


def _settled(target: Path, job_ids: Sequence[str], run: SweepRun, wanted: Callable[[], RunHeader]) -> bool:
    """True when `target` holds a complete run of `job_ids` recorded with the settings of `wanted()` (computed
    only when the rest agrees). A finished run whose settings differ is refused, with the resume check's message."""
    from talkdem.runs.spec import MERGE_KEYS, check_same_run

    if not (target / HEADER_FILE).is_file():
        return False
    header = read_header(target)
    if header.status != "complete" or not set(job_ids) <= {e.episode_id for e in read_episodes(target)}:
        return False
    if header.model.get("backend") != run.backend or not _same_model(header.model.get("name", ""), run.model):
        return False  # the job's own resume check decides, with the model loaded
    keys = [k for k in MERGE_KEYS if k != "model" and (k != "config.limit" or "limit" in header.config)]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        check_same_run(target, header, wanted(), keys)
    return True


def _same_model(recorded: str, model: str) -> bool:
    from talkdem.llm.interface.models import get_model

    spec = get_model(model)
    return recorded == (spec.name if spec is not None else model) or Path(recorded).name == Path(model).name


def wanted_header(run: SweepRun) -> RunHeader:
    """The header `talkdem run` would write for `run`, but for the model identity (no model is loaded): what a
    finished run directory is compared with before its job is skipped."""
    from talkdem.planner.strategies import load_strategy
    from talkdem.runs.plan import plan_run
    from talkdem.runs.spec import RunSpec

    plan = plan_run(run.job(out=run.run_dir, threads=1))
    strategy = load_strategy(run.strategy, **plan.strategy_options)
    spec = RunSpec.for_run(
        plan.config, strategy, backend_args={"backend": run.backend, **plan.backend_args}, selection=plan.extra
    )
    return spec.header(model={"backend": run.backend}, planned_episodes=len(plan.episodes))


def prepare(spec: SweepSpec, run: SweepRun, shards: int) -> RunWork:
    """The jobs of `run` in `shards` shards (fewer when the run has fewer episodes; an interrupted sweep's own
    count when its shard folders are there), those already settled left out."""
    from talkdem.instructions import load_instructions

    folder = work_folder(spec.out) / run.name
    shutil.rmtree(_removing(folder), ignore_errors=True)  # a clean-up cut short: the run is merged already
    cache: list[RunHeader] = []

    def wanted() -> RunHeader:
        if not cache:
            cache.append(wanted_header(run))
        return cache[0]

    notes: list[str] = []
    has_run = _has_run(run.run_dir)
    count = _existing_shards(folder)
    if count is None:
        whole = Job(run, run.run_dir, None, run.episode_ids)
        if has_run and _settled(run.run_dir, run.episode_ids, run, wanted):
            return RunWork(run, [whole], [], merged=True)
        count = min(shards, len(run.episode_ids))
        if count == 1:
            return RunWork(run, [whole], [whole])
        if has_run:
            split_run(run.run_dir, count, folder, spec.conditions, spec.tasks)
            notes.append(f"{run.name}: split into {count} shards seeded with its finished episodes")
    else:
        if count != shards:
            notes.append(f"{run.name}: resuming its {count} shard folders (not {shards})")
        if has_run:
            _check_covered(run.run_dir, folder, count)
    by_id = {i.id: i for i in load_instructions()}
    selection = [by_id[i] for i in run.episode_ids]
    jobs = []
    for index in range(1, count + 1):
        shard = Shard(index, count)
        ids = tuple(i.id for i in shard_of(selection, shard))
        jobs.append(Job(run, shard_folder(folder, shard), shard, ids))
    pending = [job for job in jobs if not _settled(job.target, job.episode_ids, run, wanted)]
    return RunWork(run, jobs, pending, notes=notes)


def _removing(folder: Path) -> Path:
    return folder.with_name(f"{folder.name}.removing")


def _check_covered(run_dir: Path, folder: Path, count: int) -> None:
    """A run directory beside shard folders (a merge whose clean-up was cut short, or a run written meanwhile):
    every episode of it must be in a shard, since the merge replaces it."""
    shards = [shard_folder(folder, Shard(i, count)) for i in range(1, count + 1)]
    in_shards = {e.episode_id for shard in shards if (shard / HEADER_FILE).is_file() for e in read_episodes(shard)}
    stray = [e.episode_id for e in read_episodes(run_dir) if e.episode_id not in in_shards]
    if stray:
        raise ValueError(
            f"{run_dir}: holds {len(stray)} episodes that its shards under {folder} do not (e.g. {stray[0]}); "
            "merge them by hand (`talkdem merge`) or move one of the two away"
        )


def finish(spec: SweepSpec, work: RunWork) -> None:
    """Merge a sharded run's finished shards into its run directory (replacing what was there, which the
    shards hold), then remove the shard folders."""
    if work.merged or not work.sharded:
        work.merged = True
        return
    folder = work.jobs[0].target.parent
    staging = folder / "merged"
    shutil.rmtree(staging, ignore_errors=True)  # a merge cut short: it is made again from the shards
    merge_runs(staging, [job.target for job in work.jobs])
    run_dir = work.run.run_dir
    run_dir.parent.mkdir(parents=True, exist_ok=True)
    if run_dir.exists():
        replaced = folder / "replaced"
        shutil.rmtree(replaced, ignore_errors=True)
        with run_lock(run_dir):  # not while a `talkdem run` of it is writing
            os.rename(run_dir, replaced)
            os.rename(staging, run_dir)
    else:
        os.rename(staging, run_dir)
    # Renamed first, so that a removal cut short never leaves a partial set of shards to resume.
    os.rename(folder, _removing(folder))
    shutil.rmtree(_removing(folder))
    work.merged = True
    parent = folder.parent
    if parent.is_dir() and not any(parent.iterdir()):
        parent.rmdir()
