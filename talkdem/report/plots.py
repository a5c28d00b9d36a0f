"""The report's figures from scored runs (matplotlib, Agg backend, imported only when plotting).

Every figure keeps unlike runs apart: nothing averages over runs unless they covered the same episodes,
the reference-plan oracle is drawn hatched (bars) or left out where it holds by construction (retention),
legends sit outside the axes, and a bar of height zero is still drawn.
"""

from __future__ import annotations

import math
import textwrap
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from talkdem.report.public import unique_stems
from talkdem.report.runs import STRATEGY_LABELS, ScoredRun
from talkdem.report.table import PATTERN_CODES, PATTERN_LABELS
from talkdem.schema import LEVELS, PATTERN_CONFIGS

__all__ = [
    "PlotFile",
    "heatmap_figure",
    "radar_figure",
    "radar_limit",
    "retention_figure",
    "success_figure",
    "write_plots",
]

_DPI = 120


@dataclass(frozen=True)
class PlotFile:
    """A written figure with what a reader needs to know about it."""

    path: Path
    title: str
    caption: str


def _pyplot() -> Any:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _pct(value: float | None) -> float:
    return math.nan if value is None or math.isnan(value) else 100 * value


def _interval(run: ScoredRun, key: str) -> tuple[float, float] | None:
    found = run.scores.intervals.get(key)
    if found is None or any(math.isnan(v) for v in found):
        return None
    return 100 * found[0], 100 * found[1]


def _one_line(text: str) -> str:
    return " ".join(text.split())


def _legend_label(run: ScoredRun) -> str:
    tag = " (reference plans, not ranked)" if run.is_reference else ""
    label = _one_line(run.label if not run.is_reference else run.model)
    tasks = run.coverage.tasks
    return f"{label}{tag}: {tasks} task{'' if tasks == 1 else 's'}"


def _same_episodes(runs: Sequence[ScoredRun]) -> bool:
    return len({(r.header.dataset_hash, r.coverage.task_set) for r in runs}) == 1


def success_figure(runs: Sequence[ScoredRun]) -> Any:
    """Bars: SR (%) on clean and each pattern (mean over levels), one bar per run, with 95% bootstrap
    intervals; `*` marks a significant change from clean (paired t-test, p<0.05)."""
    plt = _pyplot()
    groups = ["Clean", *(PATTERN_CODES[p] for p in PATTERN_CONFIGS)]
    keys = ["clean", *PATTERN_CONFIGS]
    width = 0.8 / len(runs)
    fig, ax = plt.subplots(figsize=(max(7.5, 1.1 * len(groups) * len(runs) * 0.3 + 3), 4.8), layout="constrained")
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    any_interval = False
    for i, run in enumerate(runs):
        color = "#9e9e9e" if run.is_reference else colors[i % len(colors)]
        values = [_pct(run.scores.success_rate[k]) for k in keys]
        xs = [g + (i - (len(runs) - 1) / 2) * width for g in range(len(groups))]
        ax.bar(
            xs,
            [0 if math.isnan(v) else v for v in values],
            width * 0.92,
            color=color,
            hatch="//" if run.is_reference else None,
            edgecolor="white" if run.is_reference else color,
            label=_legend_label(run),
        )
        for x, value, key in zip(xs, values, keys, strict=True):
            interval = _interval(run, f"sr/{key}")
            if interval is not None and not math.isnan(value):
                any_interval = True
                ax.errorbar(
                    x,
                    value,
                    yerr=[[value - interval[0]], [interval[1] - value]],
                    color="black",
                    capsize=2,
                    linewidth=0.8,
                )
            if math.isnan(value):
                ax.text(x, 1.5, "n/a", ha="center", va="bottom", fontsize=6, rotation=90, color="#555")
            elif value == 0:
                # A zero bar has no height: a stub on the axis and a 0 keep it from reading as "missing".
                ax.plot(
                    [x - width * 0.46, x + width * 0.46],
                    [0, 0],
                    color=color,
                    linewidth=4,
                    solid_capstyle="butt",
                    clip_on=False,
                )
                ax.text(x, 1.5, "0", ha="center", va="bottom", fontsize=7, color="#333")
        for x, value, pattern in zip(xs[1:], values[1:], PATTERN_CONFIGS, strict=True):
            p_value = run.scores.sr_change_test[pattern].p_value
            if not math.isnan(p_value) and p_value < 0.05 and not math.isnan(value):
                top = _interval(run, f"sr/{pattern}")
                ax.text(x, (top[1] if top else value) + 1, "*", ha="center", va="bottom", fontsize=11)
    ax.set_xticks(range(len(groups)), groups)
    ax.set_ylabel("Task success rate (%)")
    ax.set_ylim(0, 110)
    ax.spines[["top", "right"]].set_visible(False)
    whiskers = "whiskers: 95% bootstrap interval over tasks" if any_interval else "no intervals (bootstrap off)"
    ax.set_title(f"Success rate per pattern (mean over levels); {whiskers}; *: p<0.05 vs clean", fontsize=9)
    fig.legend(loc="outside lower center", ncols=min(2, len(runs)), fontsize=7, frameon=False)
    return fig


def retention_figure(runs: Sequence[ScoredRun], *, paper: bool = False) -> Any:
    """Retention (%) against level per pattern, one line per run. The oracle is left out (its retention is
    100% by construction); a mean line is drawn only over runs that covered the same episodes. With `paper`,
    a gray dotted line is the paper's mean over its six open-weight models (other models)."""
    plt = _pyplot()
    paper_means = {}
    if paper:
        from talkdem.report.paper import paper_retention_means

        paper_means = paper_retention_means()
    undefined = [
        r
        for r in runs
        if not r.is_reference and not any(not math.isnan(v) for v in (r.scores.retention or {}).values())
    ]
    shown = [r for r in runs if not r.is_reference and r not in undefined]
    fig, axes = plt.subplots(
        1, len(PATTERN_CONFIGS), figsize=(3.0 * len(PATTERN_CONFIGS), 3.9), sharey=True, layout="constrained"
    )
    mean_label = ""
    for ax, pattern in zip(axes, PATTERN_CONFIGS, strict=True):
        curves = []
        for run in shown:
            retention = run.scores.retention or {}
            values = [_pct(retention.get(f"{pattern}:{level}", math.nan)) for level in LEVELS]
            curves.append(values)
            ax.plot(LEVELS, values, marker="o", linewidth=1.2, alpha=0.8, label=_legend_label(run))
        if len(shown) > 1 and _same_episodes(shown):
            mean = []
            for column in zip(*curves, strict=True):
                finite = [v for v in column if not math.isnan(v)]
                mean.append(sum(finite) / len(finite) if len(finite) == len(column) else math.nan)
            mean_label = f"mean of the {len(shown)} runs (same episodes)"
            # A wide dash marker keeps the mean visible where a run covers one level (a line needs two points).
            ax.plot(LEVELS, mean, color="black", linewidth=2.5, marker="_", markersize=16, mew=2.5, label=mean_label)
        if paper_means:
            values = [paper_means.get((pattern, level), math.nan) for level in LEVELS]
            label = "the paper: mean of its six open-weight models (other models)"
            ax.plot(LEVELS, values, color="gray", linestyle=":", linewidth=2, marker="s", markersize=4, label=label)
        ax.axhline(100, color="gray", linestyle="--", linewidth=1)
        ax.set_xticks(LEVELS, [f"L{level}" for level in LEVELS])
        ax.set_title(PATTERN_LABELS[pattern], fontsize=9)
        ax.set_ylim(-3, 105)
        ax.spines[["top", "right"]].set_visible(False)
    axes[0].set_ylabel("Clean-conditioned retention (%)")
    if shown or paper_means:
        fig.legend(*axes[0].get_legend_handles_labels(), loc="outside lower center", ncols=2, fontsize=7, frameon=False)
    if not shown:
        fig.text(0.5, 0.5, "No run with a defined retention to show", ha="center", fontsize=10)
    note = "dashed: the clean baseline (100%)"
    if not mean_label and len(shown) > 1:
        note += "; no mean line: the runs covered different episodes"
    if any(r.is_reference for r in runs):
        note += "; reference plans omitted (100% by construction)"
    if undefined:
        names = ", ".join(_one_line(r.label) for r in undefined)
        note += f"; omitted, no task solved under clean (retention undefined): {names}"
    fig.suptitle(f"Retention per intensity level\n({note})", fontsize=9)
    return fig


def heatmap_figure(run: ScoredRun) -> Any:
    """Pattern x level heatmaps of one run: success rate and retention (%), values written in each cell,
    conditions not run in gray."""
    plt = _pyplot()
    import numpy as np

    fig, axes = plt.subplots(1, 2, figsize=(9.6, 3.9), layout="constrained")
    retention = run.scores.retention or {}
    panels = (
        (
            "Success rate (%)",
            {f"{p}:{lv}": run.scores.success_rate.get(f"{p}:{lv}", math.nan) for p in PATTERN_CONFIGS for lv in LEVELS},
        ),
        (
            "Retention (%)",
            {f"{p}:{lv}": retention.get(f"{p}:{lv}", math.nan) for p in PATTERN_CONFIGS for lv in LEVELS},
        ),
    )
    cmap = plt.get_cmap("viridis").with_extremes(bad="#d9d9d9")
    image = None
    for ax, (name, values) in zip(axes, panels, strict=True):
        grid = np.array([[_pct(values[f"{p}:{lv}"]) for lv in LEVELS] for p in PATTERN_CONFIGS])
        image = ax.imshow(np.ma.masked_invalid(grid), cmap=cmap, vmin=0, vmax=100, aspect="auto")
        for row in range(len(PATTERN_CONFIGS)):
            for col in range(len(LEVELS)):
                value = grid[row, col]
                text = "n/a" if math.isnan(value) else f"{value:.0f}"
                dark = not math.isnan(value) and value < 60
                ax.text(col, row, text, ha="center", va="center", fontsize=9, color="white" if dark else "black")
        ax.set_xticks(range(len(LEVELS)), [f"L{lv}" for lv in LEVELS])
        ax.set_yticks(range(len(PATTERN_CONFIGS)), [PATTERN_LABELS[p] for p in PATTERN_CONFIGS], fontsize=8)
        if np.all(np.isnan(grid)):
            name += "\nundefined: no task solved under clean" if name.startswith("Retention") else "\nnot run"
        ax.set_title(name, fontsize=9)
    fig.colorbar(image, ax=axes, shrink=0.85, label="%")
    clean = _pct(run.scores.success_rate["clean"])
    clean_text = "n/a" if math.isnan(clean) else f"{clean:.1f}%"
    title = _one_line(run.label) if not run.is_reference else f"{run.model} (reference plans)"
    fig.suptitle(f"{title}: clean SR {clean_text}; {run.coverage.describe()}", fontsize=9)
    return fig


def _strategy_order(name: str) -> tuple[int, str]:
    order = list(STRATEGY_LABELS.values())
    return (order.index(name) if name in order else len(order), name)


def radar_limit(values: Sequence[float]) -> int:
    """The radar's radial limit (%) for these values: the largest rounded up to a multiple of 10, from 10 to 100."""
    largest = max(values, default=0.0)
    return int(min(100, max(10, 10 * math.ceil(largest / 10))))


def _radar_values(run: ScoredRun) -> list[float]:
    """SR (%) on clean and each pattern, in the radar's axis order; a condition not run is drawn at 0."""
    values = [_pct(run.scores.success_rate[k]) for k in ("clean", *PATTERN_CONFIGS)]
    return [0.0 if math.isnan(v) else v for v in values]


def radar_figure(runs: Sequence[ScoredRun]) -> tuple[Any, str]:
    """Radar charts: one per model run under two or more strategies, SR (%) on clean and each pattern, one
    polygon per strategy. Only planner runs with a non-zero value take part; the returned note says which
    runs were left out, and why (an empty figure says so in words), and where the radial axis ends below 100%."""
    plt = _pyplot()
    planner_runs = [r for r in runs if r.compared_as_strategy]
    zero = [r for r in planner_runs if not any(_pct(r.scores.success_rate[k]) > 0 for k in ("clean", *PATTERN_CONFIGS))]
    kept = [r for r in planner_runs if r not in zero]
    notes = []
    external = sum(not r.from_planner for r in runs)
    asking = sum(r.from_planner and r.clarify != "none" for r in runs)
    if external:
        notes.append(f"{external} run(s) without a prompting strategy (external or reference plans) are not strategies")
    if asking:
        notes.append(f"{asking} run(s) with questions are compared in the clarification table, not here")
    if zero:
        notes.append("left out, every success rate 0: " + ", ".join(_one_line(r.label) for r in zero))
    models: dict[str, list[ScoredRun]] = {}
    for run in kept:
        models.setdefault(run.model, []).append(run)
    single = [m for m, group in models.items() if len({r.strategy for r in group}) < 2]
    if single:
        notes.append("one strategy only, nothing to compare: " + ", ".join(_one_line(m) for m in single))
        models = {m: g for m, g in models.items() if m not in single}
    # The radial axis ends at the largest value drawn, rounded up to 10 points: at 0-100 a small model's polygons
    # (success rates of 5-25%) crowd the centre and their differences cannot be read. Shared by every chart of
    # the figure, so polygons of different models stay comparable, and stated on the figure when it is not 0-100.
    radial_max = radar_limit([v for group in models.values() for r in group for v in _radar_values(r)])
    if models and radial_max < 100:
        notes.append(f"radial axis 0-{radial_max}% (the largest success rate drawn, rounded up), not 0-100%")
    note = "; ".join(notes)
    if not models:
        fig, ax = plt.subplots(figsize=(7.0, 2.4))
        ax.axis("off")
        if not planner_runs:
            reason = "no planner runs"
        elif not kept:
            reason = "every planner run scored 0 on every condition"
        else:
            reason = "no model was run with two or more strategies"
        ax.text(0.5, 0.6, f"No strategy comparison to draw: {reason}.", ha="center", va="center", fontsize=11)
        ax.text(0.5, 0.3, note, ha="center", va="center", fontsize=8, wrap=True)
        return fig, f"Empty: {reason}. {note}".strip()
    axes_labels = ["Clean", *(PATTERN_CODES[p] for p in PATTERN_CONFIGS)]
    angles = [2 * math.pi * i / len(axes_labels) for i in range(len(axes_labels))]
    fig, axes = plt.subplots(
        1,
        len(models),
        figsize=(max(6.0, 4.4 * len(models)), 5.4),
        subplot_kw={"projection": "polar"},
        squeeze=False,
        layout="constrained",
    )
    # One color per strategy across the charts, so a single legend serves them all.
    palette = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    strategies = sorted({r.strategy for g in models.values() for r in g}, key=_strategy_order)
    color = {name: palette[i % len(palette)] for i, name in enumerate(strategies)}
    for ax, (model, group) in zip(axes[0], models.items(), strict=True):
        for run in group:
            values = _radar_values(run)
            closed = [*values, values[0]]
            ax.plot([*angles, angles[0]], closed, linewidth=1.5, color=color[run.strategy], label=run.strategy)
            ax.fill([*angles, angles[0]], closed, alpha=0.08, color=color[run.strategy])
        ax.set_xticks(angles, axes_labels)
        ax.set_ylim(0, radial_max)
        ax.set_rlabel_position(360 / len(axes_labels) / 2)  # between two axes, clear of their labels
        ax.set_title(_one_line(model), fontsize=9)
    handles = [plt.Line2D([], [], color=color[name], linewidth=1.5, label=name) for name in strategies]
    fig.legend(handles=handles, loc="outside lower center", ncols=min(6, len(handles)), fontsize=8, frameon=False)
    if note:
        fig.suptitle(textwrap.fill(note, width=int(20 * fig.get_figwidth())), fontsize=7)
    return fig, note


def _save(fig: Any, path: Path) -> Path:
    fig.savefig(path, dpi=_DPI)
    _pyplot().close(fig)
    return path


def write_plots(runs: Sequence[ScoredRun], folder: Path, *, paper: bool = False) -> list[PlotFile]:
    """Every figure as a PNG in `folder`: bars, retention lines, the strategy radar, a heatmap per run; with
    `paper`, the retention figure also draws the paper's mean (other models)."""
    folder.mkdir(parents=True, exist_ok=True)
    files = [
        PlotFile(
            _save(success_figure(runs), folder / "success_by_pattern.png"),
            "Success rate per pattern",
            "Success rate (%) on clean instructions and under each pattern (mean over its three levels), one bar "
            "per run with its 95% bootstrap interval over tasks; hatched: reference plans (not ranked).",
        ),
        PlotFile(
            _save(retention_figure(runs, paper=paper), folder / "retention_by_level.png"),
            "Retention per intensity level",
            "Clean-conditioned retention (%) per pattern and level, one line per run."
            + (
                " Gray dotted: the paper's mean over its six open-weight models (7B-72B, its 300 tasks and dataset "
                "build; other models, for direction only)."
                if paper
                else ""
            ),
        ),
    ]
    radar, note = radar_figure(runs)
    files.append(
        PlotFile(
            _save(radar, folder / "strategy_radar.png"),
            "Prompting strategies",
            "Success rate (%) on clean and each pattern per strategy, one chart per model. " + note,
        )
    )
    for run, stem in zip(runs, unique_stems([r.label for r in runs]), strict=True):
        files.append(
            PlotFile(
                _save(heatmap_figure(run), folder / f"heatmap_{stem}.png"),
                f"Pattern x level: {run.label}",
                f"Success rate and retention (%) of {run.label} per pattern and level; gray (n/a): not run, or "
                "retention undefined (no task solved under clean).",
            )
        )
    return files
