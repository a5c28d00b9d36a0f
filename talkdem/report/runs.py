"""Scored runs: a run directory's header with the scores of its stored episodes (nothing is re-executed)."""

from __future__ import annotations

import hashlib
import json
from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path

from talkdem.metrics import Scores, compute_scores, results_from_run
from talkdem.metrics.stats import BOOTSTRAP_SEED
from talkdem.planner.strategies import STRATEGIES
from talkdem.report.coverage import Coverage, coverage_of
from talkdem.report.public import public_model
from talkdem.runs import RunHeader, read_header
from talkdem.runs.oracle import ORACLE_STRATEGY

__all__ = [
    "REFERENCE_STRATEGY",
    "STRATEGY_LABELS",
    "ScoredRun",
    "run_key",
    "run_keys",
    "run_labels",
    "score_runs",
    "strategy_label",
]

STRATEGY_LABELS = STRATEGIES.labels()
"""Registered strategy name -> the label tables and plots show."""
"""The paper's names of the prompting strategies, in its column order."""


def strategy_label(name: str) -> str:
    return STRATEGY_LABELS.get(name.lower(), name)


REFERENCE_STRATEGY = ORACLE_STRATEGY
"""The strategy name of the oracle run (defined once, in `talkdem.runs.oracle`)."""


@dataclass(frozen=True)
class ScoredRun:
    """One run: where it lives, its header, a unique label, and its scores."""

    run_dir: Path
    header: RunHeader
    label: str
    scores: Scores

    @property
    def key(self) -> str:
        """The run's key (`run_key`): what labels files and error samples name it by."""
        return run_key(self.run_dir, self.header)

    @property
    def model(self) -> str:
        return public_model(self.header.model)["name"] or "unknown model"

    @property
    def strategy(self) -> str:
        return strategy_label(self.header.strategy)

    @property
    def clarify(self) -> str:
        """`oracle`, `in-pattern`, or `none` (also for runs from before clarification existed)."""
        return _clarify_of(self.header)

    @property
    def setting(self) -> str:
        """The strategy as a table names it: `Vanilla`, or `Vanilla + ask (oracle)` for a clarification run,
        so that a run with questions is never read as the same strategy without them."""
        return _setting_of(self.header)

    @property
    def compared_as_strategy(self) -> bool:
        """Whether the run takes part in strategy comparisons: a planner run without questions (an oracle or
        external run has no strategy; a clarification run has its own comparison, the clarification table)."""
        return self.from_planner and self.clarify == "none"

    @property
    def from_planner(self) -> bool:
        """False for plans written elsewhere (`talkdem score`, the oracle): they have no prompting strategy."""
        return self.header.planner != "external"

    @property
    def is_reference(self) -> bool:
        """The oracle: the tasks' reference plans, an upper bound shown apart and never ranked."""
        return self.header.planner == "external" and self.header.strategy == REFERENCE_STRATEGY

    @cached_property
    def coverage(self) -> Coverage:
        planned = self.header.config.get("planned_episodes")
        return coverage_of(self.scores, planned if isinstance(planned, int) else None)


def score_runs(run_dirs: Sequence[Path], *, bootstrap: int = 1000, seed: int = BOOTSTRAP_SEED) -> list[ScoredRun]:
    """Score each run directory; labels (`model / strategy`) are made unique with the run's key (`run_labels`)."""
    if not run_dirs:
        raise ValueError("no run directories given")
    runs = []
    headers = [read_header(run_dir) for run_dir in run_dirs]
    for run_dir, header, label in zip(run_dirs, headers, run_labels(run_dirs, headers), strict=True):
        scores = compute_scores(results_from_run(run_dir, run=label), bootstrap=bootstrap, seed=seed)
        runs.append(ScoredRun(run_dir, header, label, scores))
    return runs


def _clarify_of(header: RunHeader) -> str:
    """Who answered the run's questions: `oracle`, `in-pattern`, or `none`."""
    return str(header.config.get("clarify", "none"))


def _setting_of(header: RunHeader) -> str:
    """The strategy's label, with ` + ask (<mode>)` for a clarification run (beside the same run without it)."""
    clarify = _clarify_of(header)
    strategy = strategy_label(header.strategy)
    return strategy if clarify == "none" else f"{strategy} + ask ({clarify})"


def run_key(run_dir: Path, header: RunHeader) -> str:
    """8 hex digits naming a run for good: a hash of what a run keeps for life (its folder's name and the name
    of the folder holding it, model, planner, strategy, prompt version, start time, shard and clarification
    mode; not what a resume changes), the same whichever runs it is shown with and in whatever order. Labels
    made in the viewer are matched to the report's runs by it, never by the display label (which depends on
    the runs shown beside it). The parent folder's name tells apart a run and its extension kept beside it
    (`runs/X` holding level 3 of `runs/levels/X`, with the same header otherwise)."""
    identity = {
        "folder": "/".join(run_dir.resolve().parts[-2:]),
        "model": header.model,
        "planner": header.planner,
        "strategy": header.strategy,
        "prompt_version": header.prompt_version,
        "created": header.created,
        "shard": header.config.get("shard"),
        "clarify": header.config.get("clarify"),
    }
    return hashlib.sha256(json.dumps(identity, sort_keys=True, default=str).encode()).hexdigest()[:8]


def run_keys(run_dirs: Sequence[Path], headers: Sequence[RunHeader]) -> list[str]:
    """`run_key` of each run; one run given twice (the same folder, or a copy of it under the same two folder
    names) is refused: its episodes would count twice and its labels could not be told apart."""
    keys = [run_key(run_dir, header) for run_dir, header in zip(run_dirs, headers, strict=True)]
    first: dict[str, Path] = {}
    for run_dir, key in zip(run_dirs, keys, strict=True):
        if key in first:
            raise ValueError(
                f"{run_dir}: the same run as {first[key]} (same folder names and header); give each run once"
            )
        first[key] = run_dir
    return keys


def run_labels(run_dirs: Sequence[Path], headers: Sequence[RunHeader]) -> list[str]:
    """`model / strategy` per run; runs whose labels would be the same get their key in brackets
    (`model / CARE [1a2b3c4d]`), so a label never depends on the order the runs are given in (the report,
    the viewer and the error sample name runs alike)."""
    keys = run_keys(run_dirs, headers)
    # Labels are published (tables, legends, file names): a model file is named by its file name.
    labels = [f"{public_model(h.model)['name'] or 'unknown model'} / {_setting_of(h)}" for h in headers]
    counts = Counter(labels)
    labels = [f"{label} [{key}]" if counts[label] > 1 else label for label, key in zip(labels, keys, strict=True)]
    if len(set(labels)) < len(labels):
        # A suffixed label now equals one a run had from the start (a strategy named like a suffixed label):
        # every label takes its key. Suffixes have one length and keys are distinct, so no two can be equal.
        labels = [f"{label} [{key}]" for label, key in zip(labels, keys, strict=True)]
    return labels
