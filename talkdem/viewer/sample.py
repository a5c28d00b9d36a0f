"""The paper's error-analysis sample (section "Error Analysis"): among the pattern episodes that failed while
the clean instruction of the same task succeeded, N drawn at random per model and pattern-level (the paper:
3 from each of six open-weight models under each of the 15 conditions, 270 failures), to be labelled by hand.

Here a run is one model under one strategy, so the draw is per run and condition. It is seeded and
deterministic: candidates are sorted by episode id before drawing, so the same runs and seed give the same
sample whatever order the episodes were stored in. A condition with fewer candidates than N gives all it has
(the file says how many were short).
"""

from __future__ import annotations

import random
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from talkdem.metrics.errors import ErrorType
from talkdem.schema import CONDITIONS
from talkdem.viewer.episodes import ViewedRun

__all__ = ["SAMPLE_SCHEMA", "ErrorSample", "SampledFailure", "read_sample", "sample_errors"]

SAMPLE_SCHEMA = "talkdem-error-sample/1"


@dataclass(frozen=True)
class SampledFailure:
    run: str
    """The run's label (`model / strategy`, as the report names it)."""
    episode_id: str
    condition: str
    """`pattern:level`."""
    automatic: ErrorType
    reason: str
    run_key: str = ""
    """The run's key (`talkdem.report.runs.run_key`): the sample names its runs by it (labels depend on the
    runs shown together)."""


@dataclass(frozen=True)
class ErrorSample:
    seed: int
    per_condition: int
    runs: tuple[str, ...]
    failures: tuple[SampledFailure, ...]
    short: tuple[tuple[str, str, int], ...]
    """(run, condition, candidates) where fewer than `per_condition` failures were available."""

    def to_json(self) -> dict[str, Any]:
        return {
            "schema": SAMPLE_SCHEMA,
            "seed": self.seed,
            "per_condition": self.per_condition,
            "runs": list(self.runs),
            "episodes": [
                {
                    "run": f.run,
                    "run_key": f.run_key,
                    "episode_id": f.episode_id,
                    "condition": f.condition,
                    "automatic": f.automatic.value,
                    "reason": f.reason,
                }
                for f in self.failures
            ],
            "short": [{"run": r, "condition": c, "available": n} for r, c, n in self.short],
        }


def sample_errors(runs: Sequence[ViewedRun], per_condition: int = 3, seed: int = 0) -> ErrorSample:
    """Draw `per_condition` failures per run and pattern condition (see the module docstring)."""
    if per_condition < 1:
        raise ValueError(f"per_condition must be at least 1, got {per_condition}")
    rng = random.Random(seed)
    failures: list[SampledFailure] = []
    short: list[tuple[str, str, int]] = []
    for run in runs:
        by_condition: dict[str, list[SampledFailure]] = {}
        for episode in run.episodes:
            if not episode.in_error_analysis:
                continue
            assert episode.error is not None
            condition = str(episode.record.condition)
            by_condition.setdefault(condition, []).append(
                SampledFailure(
                    run.label, episode.episode_id, condition, episode.error.type, episode.error.reason, run.key
                )
            )
        covered = {str(e.record.condition) for e in run.episodes}
        # Conditions in the benchmark's order, so the draw does not depend on which one a run stored first.
        for condition in (str(c) for c in CONDITIONS if not c.is_clean):
            candidates = sorted(by_condition.get(condition, []), key=lambda f: f.episode_id)
            if condition not in covered:
                continue  # a condition the run did not cover is not short of failures
            if len(candidates) < per_condition:
                short.append((run.label, condition, len(candidates)))
            failures += rng.sample(candidates, min(per_condition, len(candidates)))
    return ErrorSample(seed, per_condition, tuple(r.label for r in runs), tuple(failures), tuple(short))


_ENTRY_TEXT = ("run", "episode_id")
_ENTRY_OPTIONAL_TEXT = ("run_key", "condition", "reason")


def _whole(value: object, least: int) -> bool:
    return isinstance(value, int) and not isinstance(value, bool) and least <= value <= 2**31 - 1


def read_sample(path: Path) -> dict[str, Any]:
    """A sample file written by `talkdem sample-errors`, checked for its shape (the viewer embeds it): one
    error naming the file and the field (or episode) that is wrong."""
    from talkdem.viewer.json_files import read_json_file

    data = read_json_file(path, "an error sample")
    if not isinstance(data, dict) or data.get("schema") != SAMPLE_SCHEMA:
        raise ValueError(f"{path}: not an error sample (expected a JSON object with schema {SAMPLE_SCHEMA!r})")
    for name, least in (("seed", 0), ("per_condition", 1)):
        if not _whole(data.get(name), least):
            raise ValueError(f"{path}: field '{name}' must be a whole number, {least} or more, got {data.get(name)!r}")
    episodes = data.get("episodes")
    if not isinstance(episodes, list):
        raise ValueError(f"{path}: field 'episodes' must be a list")
    types = {t.value for t in ErrorType}
    for n, entry in enumerate(episodes, start=1):
        if not isinstance(entry, dict) or not all(isinstance(entry.get(k), str) for k in _ENTRY_TEXT):
            raise ValueError(f"{path}: episode {n}: expected an object with string fields 'run' and 'episode_id'")
        for key in _ENTRY_OPTIONAL_TEXT:
            if key in entry and not isinstance(entry[key], str):
                raise ValueError(f"{path}: episode {n}: field '{key}' must be a string")
        if "automatic" in entry and (not isinstance(entry["automatic"], str) or entry["automatic"] not in types):
            raise ValueError(f"{path}: episode {n}: field 'automatic' must be one of {', '.join(sorted(types))}")
    return data
