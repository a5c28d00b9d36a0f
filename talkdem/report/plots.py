"""The paper's figures from scored runs (matplotlib, Agg backend, imported only when plotting)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from talkdem.instructions import PATTERN_CONFIGS
from talkdem.report.runs import ScoredRun
from talkdem.report.tables import PATTERN_CODES, PATTERN_LABELS

__all__ = ["plot_retention_by_level", "plot_strategy_radar", "plot_success_by_pattern", "write_plots"]


def _pyplot() -> Any:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _pct(value: float) -> float:
    return math.nan if value is None or math.isnan(value) else 100 * value


def plot_success_by_pattern(runs: Sequence[ScoredRun], path: Path) -> Path:
    """The overall-results bar chart: SR (%) on clean and each pattern (mean over levels), one bar per run;
    `*` marks a significant change from clean (paired t-test, p<0.05)."""
    plt = _pyplot()
    groups = ["Clean", *(PATTERN_CODES[p] for p in PATTERN_CONFIGS)]
    width = 0.8 / len(runs)
    fig, ax = plt.subplots(figsize=(max(7.0, 1.2 * len(groups) * max(1, len(runs)) * 0.45), 4.0))
    for i, run in enumerate(runs):
        s = run.scores
        values = [_pct(s.success_rate["clean"]), *(_pct(s.success_rate[p]) for p in PATTERN_CONFIGS)]
        xs = [g + (i - (len(runs) - 1) / 2) * width for g in range(len(groups))]
        ax.bar(xs, values, width, label=run.label)
        for x, value, pattern in zip(xs[1:], values[1:], PATTERN_CONFIGS, strict=True):
            p_value = s.sr_change_test[pattern].p_value
            if not math.isnan(p_value) and p_value < 0.05 and not math.isnan(value):
                ax.text(x, value + 1, "*", ha="center", va="bottom", fontsize=12)
    ax.set_xticks(range(len(groups)), groups)
    ax.set_ylabel("Task success rate (%)")
    ax.set_ylim(0, 110)
    ax.legend(fontsize=7, loc="lower right")
    ax.set_title("Success rate per pattern (mean over levels); *: p<0.05 vs clean")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def plot_retention_by_level(runs: Sequence[ScoredRun], path: Path) -> Path:
    """The level figure: retention (%) against intensity per pattern; thin lines per run, black the mean,
    dashed the clean baseline (100%)."""
    plt = _pyplot()
    fig, axes = plt.subplots(1, len(PATTERN_CONFIGS), figsize=(3.0 * len(PATTERN_CONFIGS), 3.2), sharey=True)
    levels = [1, 2, 3]
    for ax, pattern in zip(axes, PATTERN_CONFIGS, strict=True):
        curves = []
        for run in runs:
            retention = run.scores.retention or {}
            values = [_pct(retention.get(f"{pattern}:{level}", math.nan)) for level in levels]
            curves.append(values)
            ax.plot(levels, values, marker="o", linewidth=1, alpha=0.7, label=run.label)
        if len(curves) > 1:
            mean = [
                sum(v for v in column if not math.isnan(v)) / max(1, sum(not math.isnan(v) for v in column))
                for column in zip(*curves, strict=True)
            ]
            ax.plot(levels, mean, color="black", linewidth=2.5, label="mean")
        ax.axhline(100, color="gray", linestyle="--", linewidth=1)
        ax.set_xticks(levels, [f"L{level}" for level in levels])
        ax.set_title(PATTERN_LABELS[pattern], fontsize=9)
        ax.set_ylim(0, 105)
    axes[0].set_ylabel("Clean-conditioned retention (%)")
    axes[-1].legend(fontsize=6, loc="lower left")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def plot_strategy_radar(runs: Sequence[ScoredRun], path: Path) -> Path:
    """Radar charts: one per model, SR (%) on clean and each pattern, one polygon per strategy."""
    plt = _pyplot()
    models: dict[str, list[ScoredRun]] = {}
    for run in [r for r in runs if r.from_planner] or runs:
        models.setdefault(run.model, []).append(run)
    axes_labels = ["Clean", *(PATTERN_CODES[p] for p in PATTERN_CONFIGS)]
    angles = [2 * math.pi * i / len(axes_labels) for i in range(len(axes_labels))]
    fig, axes = plt.subplots(
        1, len(models), figsize=(4.2 * len(models), 4.2), subplot_kw={"projection": "polar"}, squeeze=False
    )
    for ax, (model, group) in zip(axes[0], models.items(), strict=True):
        for run in group:
            s = run.scores
            values = [_pct(s.success_rate["clean"]), *(_pct(s.success_rate[p]) for p in PATTERN_CONFIGS)]
            values = [0.0 if math.isnan(v) else v for v in values]
            ax.plot([*angles, angles[0]], [*values, values[0]], linewidth=1.5, label=run.strategy)
            ax.fill([*angles, angles[0]], [*values, values[0]], alpha=0.08)
        ax.set_xticks(angles, axes_labels)
        ax.set_ylim(0, 100)
        ax.set_title(model, fontsize=9)
        ax.legend(fontsize=7, loc="lower right", bbox_to_anchor=(1.25, -0.1))
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def write_plots(runs: Sequence[ScoredRun], folder: Path) -> list[Path]:
    """All three figures as PNG files in `folder`."""
    folder.mkdir(parents=True, exist_ok=True)
    return [
        plot_success_by_pattern(runs, folder / "success_by_pattern.png"),
        plot_retention_by_level(runs, folder / "retention_by_level.png"),
        plot_strategy_radar(runs, folder / "strategy_radar.png"),
    ]
