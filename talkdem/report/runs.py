"""Scored runs: a run directory's header with the scores of its stored episodes (nothing is re-executed)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path

from talkdem.metrics import Scores, compute_scores, results_from_run
from talkdem.metrics.stats import BOOTSTRAP_SEED
from talkdem.planner.strategies import STRATEGIES
from talkdem.report.coverage import Coverage, coverage_of
from talkdem.report.public import public_model, unique_stems
from talkdem.runs import RunHeader, read_header
from talkdem.runs.oracle import ORACLE_STRATEGY

__all__ = [
    "REFERENCE_STRATEGY",
    "STRATEGY_LABELS",
    "ScoredRun",
    "run_labels",
    "score_runs",
    "slug",
    "strategy_label",
]

STRATEGY_LABELS = STRATEGIES.labels()
"""Registered strategy name -> the label tables and plots show."""
"""The paper's names of the prompting strategies, in its column order."""


def strategy_label(name: str) -> str:
    return STRATEGY_LABELS.get(name.lower(), name)


def slug(text: str) -> str:
    """A file-name-safe form of one label (`unique_stems` keeps several labels apart)."""
    return unique_stems([text])[0]


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
    """Score each run directory; labels (`model / strategy`) are made unique with a `#n` suffix."""
    if not run_dirs:
        raise ValueError("no run directories given")
    runs = []
    headers = [read_header(run_dir) for run_dir in run_dirs]
    for run_dir, header, label in zip(run_dirs, headers, run_labels(headers), strict=True):
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


def run_labels(headers: Sequence[RunHeader]) -> list[str]:
    """`model / strategy` per run, made unique with a `#n` suffix in the order given (the report, the viewer
    and the error sample name runs alike, so a labels file made in the viewer matches the report's runs)."""
    labels = []
    used: dict[str, int] = {}
    for header in headers:
        # Labels are published (tables, legends, file names): a model file is named by its file name.
        base = f"{public_model(header.model)['name'] or 'unknown model'} / {_setting_of(header)}"
        used[base] = used.get(base, 0) + 1
        labels.append(base if used[base] == 1 else f"{base} #{used[base]}")
    return labels
