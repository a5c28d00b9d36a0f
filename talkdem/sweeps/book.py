"""Which jobs of a sweep are done, and which runs are then complete (shared by the executors)."""

from __future__ import annotations

from collections.abc import Sequence

from talkdem.sweeps.spec import SweepSpec
from talkdem.sweeps.work import Job, RunWork, done_episodes, finish

__all__ = ["JobBook"]


class JobBook:
    """The works of a sweep: a job reported finished, its run merged once every job of it is; failures kept."""

    def __init__(self, spec: SweepSpec, works: Sequence[RunWork]) -> None:
        self.spec = spec
        self.works = list(works)
        self._left = {id(w): {j.key for j in w.pending} for w in self.works}
        self._of = {job.key: work for work in self.works for job in work.jobs}
        self.failures: list[str] = []
        self._failed_runs: set[str] = set()

    def start(self) -> None:
        """Merge the runs with nothing left to run (every shard settled by an earlier sitting)."""
        for work in self.works:
            if not self._left[id(work)]:
                self._finish(work)

    def pending(self) -> list[Job]:
        return [job for work in self.works for job in work.pending]

    def skip(self, job: Job) -> bool:
        """True when another job of the same run failed: the run cannot complete in this sitting."""
        return job.run.name in self._failed_runs

    def finished(self, job: Job) -> None:
        work = self._of[job.key]
        left = self._left[id(work)]
        left.discard(job.key)
        if not left and job.run.name not in self._failed_runs:
            self._finish(work)

    def failed(self, job: Job, message: str) -> None:
        self._failed_runs.add(job.run.name)
        self.failures.append(f"{job.key}: {message}")

    def _finish(self, work: RunWork) -> None:
        try:
            finish(self.spec, work)
        except (OSError, ValueError) as error:
            self._failed_runs.add(work.run.name)
            self.failures.append(f"{work.run.name}: merge failed: {str(error).splitlines()[0]}")

    def done(self, live: dict[str, int] | None = None) -> tuple[int, int]:
        """(episodes on disk, runs complete); `live`: episodes a job holds elsewhere (a Ray actor's scratch)."""
        episodes = runs = 0
        for work in self.works:
            if work.merged:
                episodes += len(work.run.episode_ids)
                runs += 1
                continue
            for job in work.jobs:
                seen = max(done_episodes(job.target), (live or {}).get(job.key, 0))
                episodes += min(seen, len(job.episode_ids))
        return episodes, runs
