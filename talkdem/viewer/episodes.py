"""The episodes of run directories as the viewer and the error sample see them: each stored record with the
outcome, hazards, plan length and automatic error type the report computes (read from its stored trace, as
the report does; a record stored without a trace is executed in the simulator) and the dataset's clean
instruction of its task.

Records are kept without the final state (the viewer never shows it, and 10,000 of them would not fit in
memory comfortably); identical plans of one task are executed once (the baseline's level-3 episodes are
also in its levels runs, and strategies often emit the same plan).
"""

from __future__ import annotations

import dataclasses
from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from talkdem.metrics.episodes import EpisodeResult, ScoringInputError, plan_length
from talkdem.metrics.errors import ErrorClassification, classify_error
from talkdem.runs import EpisodeRecord, RunHeader, read_episodes, read_header
from talkdem.schema import CLEAN, LEVELS, PATTERN_CONFIGS
from talkdem.serialization import to_jsonable
from talkdem.sim import DEFAULT_MAX_STEPS, run_plan

__all__ = ["ViewedEpisode", "ViewedRun", "load_runs"]

_SHOWN_TRACE = ("steps", "goal", "hazards", "end_reason", "dialogue")
"""The parts of a stored trace the viewer shows (`dialogue`: a clarification run's questions and answers)."""


@dataclass(frozen=True)
class ViewedEpisode:
    """One stored episode with the simulator's re-execution of its plan."""

    record: EpisodeRecord
    """As stored, with the trace reduced to its steps, goal report, hazards and end reason (those of the
    re-execution when the record stored no trace)."""
    task_type: str
    clean_text: str
    """The dataset's clean instruction of the task ("" when the dataset does not hold the instruction)."""
    success: bool
    """Re-executed (the report's outcome); `record.success` is what the run stored."""
    hazards: tuple[str, ...]
    """Hazard categories of the re-execution, in step order."""
    plan_length: int
    error: ErrorClassification | None
    """The automatic primary error type of a failure (None when the episode succeeded)."""
    clean_solved: bool | None = None
    """Whether the same run's clean episode of the task succeeded (None: the run has no clean episode)."""

    @property
    def episode_id(self) -> str:
        return self.record.episode_id

    @property
    def is_pattern(self) -> bool:
        return self.record.pattern != CLEAN

    @property
    def in_error_analysis(self) -> bool:
        """The paper's error-analysis population: failed under a pattern, solved clean (same run and task)."""
        return self.is_pattern and not self.success and self.clean_solved is True and self.error is not None


@dataclass(frozen=True)
class ViewedRun:
    """A run directory: its header, its label (as the report names it) and its episodes in stored order."""

    run_dir: Path
    header: RunHeader
    label: str
    episodes: tuple[ViewedEpisode, ...]

    @property
    def key(self) -> str:
        """The run's key (`talkdem.report.runs.run_key`): labels and error samples name the run by it."""
        from talkdem.report.runs import run_key

        return run_key(self.run_dir, self.header)


@dataclass(frozen=True)
class _Executed:
    success: bool
    hazards: tuple[str, ...]
    plan_length: int
    error: ErrorClassification | None
    shown: dict[str, Any]
    """The re-execution's steps, goal report, hazards and end reason, for records stored without a trace."""


def load_runs(run_dirs: Sequence[Path]) -> list[ViewedRun]:
    """Read and check every episode of `run_dirs`, executing only those stored without a trace (labels:
    `talkdem.report.runs.run_labels`)."""
    from talkdem.instructions import load_instructions
    from talkdem.report.runs import run_labels
    from talkdem.tasks import get_task

    if not run_dirs:
        raise ValueError("no run directories given")
    headers = [read_header(run_dir) for run_dir in run_dirs]
    instructions = {i.id: i for i in load_instructions()}
    executed: dict[tuple[str, tuple[str, ...], int], _Executed] = {}
    runs = []
    for run_dir, header, label in zip(run_dirs, headers, run_labels(run_dirs, headers), strict=True):
        records = read_episodes(run_dir)
        if not records:
            raise ScoringInputError(f"{run_dir}: the run has no episodes", [])
        counts = Counter(r.episode_id for r in records)
        duplicated = [episode_id for episode_id, n in counts.items() if n > 1]
        if duplicated:
            raise ScoringInputError(f"{run_dir}: duplicate episode ids", duplicated)
        unknown = [r.episode_id for r in records if r.pattern != CLEAN and (r.pattern, r.level) not in _KNOWN]
        if unknown:
            raise ScoringInputError(f"{run_dir}: episodes with an unknown condition", unknown)
        steps = int(header.config.get("max_steps", DEFAULT_MAX_STEPS))
        episodes = []
        for record in records:
            key = (record.task_id, record.plan, steps)
            task = get_task(record.task_id)
            if "steps" in record.trace:
                # A stored trace is the outcome (as in the report): read, not executed again.
                stored_result = EpisodeResult.from_record(record)
                assert stored_result.trace is not None
                executed[key] = _Executed(
                    stored_result.success,
                    stored_result.hazards,
                    stored_result.plan_length,
                    classify_error(task, stored_result.trace),
                    {k: record.trace[k] for k in _SHOWN_TRACE if k in record.trace},
                )
            elif key not in executed:
                trace = run_plan(task, record.plan, max_steps=steps)
                executed[key] = _Executed(
                    trace.success,
                    tuple(h.category.value for h in trace.hazards),
                    plan_length(trace),
                    classify_error(task, trace),
                    {name: to_jsonable(getattr(trace, name)) for name in _SHOWN_TRACE},
                )
            done = executed[key]
            instruction = instructions.get(record.episode_id)
            # The stored trace is what the planner was told during the run; a record without one (plans
            # scored elsewhere, hand-made runs) shows the re-execution's.
            stored = {k: record.trace[k] for k in _SHOWN_TRACE if k in record.trace}
            shown = stored if "steps" in stored else done.shown
            episodes.append(
                ViewedEpisode(
                    record=dataclasses.replace(record, trace=shown),
                    task_type=task.task_type,
                    clean_text=instruction.clean_text if instruction is not None else "",
                    success=done.success,
                    hazards=done.hazards,
                    plan_length=done.plan_length,
                    error=done.error,
                )
            )
        clean = {e.record.task_id: e.success for e in episodes if not e.is_pattern}
        episodes = [dataclasses.replace(e, clean_solved=clean.get(e.record.task_id)) for e in episodes]
        runs.append(ViewedRun(run_dir, header, label, tuple(episodes)))
    return runs


_KNOWN = {(pattern, level) for pattern in PATTERN_CONFIGS for level in LEVELS}
