"""The report folder for runs of different kinds (`mixed_runs`, conftest.py): report.html with the plots
embedded, report.md linking them, escaped Markdown, distinct file names, no machine paths; each figure."""

from __future__ import annotations

import base64
import json
import re
from pathlib import Path

from talkdem.report import ScoredRun


def test_html_page_embeds_every_plot_and_every_table(report: Path) -> None:
    page = (report / "report.html").read_text()
    images = re.findall(r'src="data:image/png;base64,([A-Za-z0-9+/=]+)"', page)
    plots = sorted((report / "plots").glob("*.png"))
    assert len(images) == len(plots) == 3 + 7  # bars, retention, radar and a heatmap per run
    assert sorted(base64.b64decode(i) for i in images) == sorted(p.read_bytes() for p in plots)
    tables = sorted(p.stem for p in (report / "tables").glob("*.json"))
    assert all(f'id="table-{name}"' in page for name in tables)
    assert "http" not in page.replace("http-equiv", "") and "<link" not in page


def test_markdown_links_its_plots(report: Path) -> None:
    text = (report / "report.md").read_text()
    linked = re.findall(r"!\[[^\]]*\]\((plots/[^)]+\.png)\)", text)
    assert sorted(linked) == sorted(f"plots/{p.name}" for p in (report / "plots").glob("*.png"))
    assert "[report.html](report.html)" in text


def test_a_pipe_or_newline_in_a_name_keeps_tables_intact(report: Path) -> None:
    for path in (report / "tables").glob("*.md"):
        rows = [line for line in path.read_text().splitlines() if line.startswith("|")]
        widths = {len(re.split(r"(?<!\\)\|", line)) for line in rows}
        assert len(widths) == 1, path.name  # every row has as many cells as the header
    success = (report / "tables" / "success.md").read_text()
    assert "my\\|model v2" in success
    page = (report / "report.html").read_text()
    assert "my|model v2" in page or "my|model\nv2" in page


def test_names_that_differ_only_in_punctuation_get_their_own_files(report: Path) -> None:
    scores = sorted(p.name for p in (report / "scores").glob("*.json"))
    assert len(scores) == 7
    assert len([s for s in scores if s.startswith("my_model_Vanilla")]) == 2
    runs = {json.loads((report / "scores" / s).read_text())["run"] for s in scores}
    assert {"my model / Vanilla", "my_model / Vanilla"} <= runs
    assert len(list((report / "plots").glob("heatmap_my_model_Vanilla*.png"))) == 2


def test_no_machine_path_in_the_report(report: Path, mixed_runs: list[ScoredRun]) -> None:
    root = str(mixed_runs[0].run_dir.parent)
    for path in report.rglob("*"):
        if path.suffix in {".md", ".csv", ".json", ".html"}:
            assert root not in path.read_text(encoding="utf-8"), path
    header = json.loads(next((report / "scores").glob("Tiny*Vanilla.json")).read_text())["header"]
    assert header["model"]["name"] == "Tiny.Q8_0.gguf"


def _extent(artist, renderer):  # type: ignore[no-untyped-def]
    return artist.get_window_extent(renderer)


def test_bars_legend_covers_no_bar_and_zero_bars_show(mixed_runs: list[ScoredRun]) -> None:
    from matplotlib.lines import Line2D
    from matplotlib.patches import Rectangle

    from talkdem.report.plots import success_figure

    fig = success_figure(mixed_runs)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    (ax,) = fig.axes
    legend = fig.legends[0]
    box = _extent(legend, renderer)
    bars = [p for p in ax.patches if isinstance(p, Rectangle)]
    assert len(bars) == 6 * len(mixed_runs)
    assert not any(box.overlaps(_extent(b, renderer)) for b in bars if b.get_height() > 0)
    assert box.y1 <= _extent(ax, renderer).y0 + 1  # below the axes
    stubs = [ln for ln in ax.lines if isinstance(ln, Line2D) and list(ln.get_ydata()) == [0, 0]]
    zeros = sum(b.get_height() == 0 for b in bars)
    assert zeros >= 6 and len(stubs) == zeros  # the all-zero run: a visible stub per bar
    # A stroke on the axis, thick and not clipped by it, as wide as the bar.
    assert all(s.get_linewidth() >= 3 and not s.get_clip_on() and _extent(s, renderer).width > 0 for s in stubs)
    assert len(ax.collections) + len([ln for ln in ax.lines if ln not in stubs]) > 0  # error bars drawn
    texts = [t.get_text() for t in ax.texts]
    assert texts.count("0") == zeros


def test_retention_averages_only_runs_over_the_same_episodes(mixed_runs: list[ScoredRun]) -> None:
    from talkdem.report.plots import retention_figure

    def labels(runs: list[ScoredRun]) -> set[str]:
        fig = retention_figure(runs)
        return {ln.get_label() for ax in fig.axes for ln in ax.lines}

    same = [r for r in mixed_runs if r.run_dir.name in {"a", "b"}]
    assert "mean of the 2 runs (same episodes)" in labels(same)
    # A run over one level gives one point per pattern: the mean needs a marker to show without a line.
    means = [ln for ax in retention_figure(same).axes for ln in ax.lines if ln.get_label().startswith("mean")]
    assert means and all(ln.get_marker() not in (None, "", "None", " ") and ln.get_markersize() >= 8 for ln in means)
    assert not any(label.startswith("mean") for label in labels(mixed_runs))  # different coverage, oracle
    assert not any("oracle" in label for label in labels(mixed_runs))


def test_radar_skips_all_zero_runs_or_says_why_it_is_empty(mixed_runs: list[ScoredRun]) -> None:
    from talkdem.report.plots import radar_figure

    fig, note = radar_figure(mixed_runs)
    drawn = {ln.get_label() for ax in fig.axes for ln in ax.lines}
    assert "CoT" not in drawn and {"Vanilla", "CARE"} <= drawn
    assert "Tiny.Q8_0.gguf / CoT" in note and "every success rate 0" in note
    assert len(fig.axes) == 1 and "one strategy only" in note  # "my model" etc. ran one strategy
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    legend, title, whole = (a.get_window_extent(renderer) for a in (fig.legends[0], fig._suptitle, fig))
    chart = fig.axes[0].get_tightbbox(renderer)
    assert not legend.overlaps(title) and not legend.overlaps(chart) and not title.overlaps(chart)
    assert all(whole.x0 <= b.x0 and b.x1 <= whole.x1 for b in (legend, title, chart))  # nothing cut off
    zero_only = [r for r in mixed_runs if r.run_dir.name == "zero"]
    fig, note = radar_figure(zero_only)
    shown = " ".join(t.get_text() for ax in fig.axes for t in ax.texts)
    assert "No strategy comparison" in shown and "scored 0" in shown


def test_radar_scale_fits_the_values_drawn_and_says_so(mixed_runs: list[ScoredRun]) -> None:
    from talkdem.report.plots import radar_figure, radar_limit

    assert [radar_limit(v) for v in ([], [0.0], [3.0, 21.7], [30.0], [85.0], [97.0], [100.0])] == [
        10,
        10,
        30,
        30,
        90,
        100,
        100,
    ]
    fig, note = radar_figure(mixed_runs)
    polar = fig.axes[0]
    drawn = [y for line in polar.lines for y in line.get_ydata()]
    top = polar.get_ylim()[1]
    assert max(drawn) <= top < max(drawn) + 10 or top == 10
    assert (f"radial axis 0-{top:.0f}%" in note) == (top < 100)


def test_heatmap_writes_every_cell(mixed_runs: list[ScoredRun]) -> None:
    from talkdem.report.plots import heatmap_figure

    zero = next(r for r in mixed_runs if r.run_dir.name == "zero")
    fig = heatmap_figure(zero)
    success, retention = fig.axes[:2]
    assert [t.get_text() for t in success.texts] == ["0"] * 15
    assert [t.get_text() for t in retention.texts] == ["n/a"] * 15  # nothing solved under clean
    assert "undefined" in retention.get_title()
