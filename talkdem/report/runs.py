"""Scored runs: a run directory's header with the scores of its re-executed plans."""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from talkdem.metrics import Scores, compute_scores, results_from_run
from talkdem.metrics.stats import BOOTSTRAP_SEED
from talkdem.runs import RunHeader, read_header

__all__ = ["STRATEGY_LABELS", "ScoredRun", "score_runs", "slug", "strategy_label"]

STRATEGY_LABELS = {"vanilla": "Vanilla", "ap": "AP", "cot": "CoT", "icl": "ICL", "tocc": "TOCC", "care": "CARE"}
"""The paper's names of the prompting strategies, in its column order."""


def strategy_label(name: str) -> str:
    return STRATEGY_LABELS.get(name.lower(), name)


def slug(text: str) -> str:
    """A file-name-safe form of a run label."""
    return re.sub(r"[^A-Za-z0-9._-]+", "_", text).strip("_") or "run"


@dataclass(frozen=True)
class ScoredRun:
    """One run: where it lives, its header, a unique label, and its scores."""

    run_dir: Path
    header: RunHeader
    label: str
    scores: Scores

    @property
    def model(self) -> str:
        return self.header.model.get("name", "") or "unknown model"

    @property
    def strategy(self) -> str:
        return strategy_label(self.header.strategy)

    @property
    def from_planner(self) -> bool:
        """False for plans written elsewhere (`talkdem score`, the oracle): they have no prompting strategy."""
        return self.header.planner != "external"


def score_runs(run_dirs: Sequence[Path], *, bootstrap: int = 1000, seed: int = BOOTSTRAP_SEED) -> list[ScoredRun]:
    """Score each run directory; labels (`model / strategy`) are made unique with a `#n` suffix."""
    if not run_dirs:
        raise ValueError("no run directories given")
    runs = []
    used: dict[str, int] = {}
    for run_dir in run_dirs:
        header = read_header(run_dir)
        base = f"{header.model.get('name', '') or 'unknown model'} / {strategy_label(header.strategy)}"
        used[base] = used.get(base, 0) + 1
        label = base if used[base] == 1 else f"{base} #{used[base]}"
        scores = compute_scores(results_from_run(run_dir, run=label), bootstrap=bootstrap, seed=seed)
        runs.append(ScoredRun(run_dir, header, label, scores))
    return runs
