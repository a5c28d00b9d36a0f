"""Write a report folder: every table as .md/.csv/.json, report.md and report.html with all of them,
scores, figures. Published files name runs by label and run-directory name, never by machine path."""

from __future__ import annotations

import json
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

from talkdem.report.public import public_header, unique_stems
from talkdem.report.runs import ScoredRun
from talkdem.report.table import Table, markdown_text
from talkdem.report.tables import all_tables
from talkdem.runs.runtime import describe_runtimes

__all__ = ["ReportFiles", "write_report"]


@dataclass
class ReportFiles:
    """What `write_report` wrote."""

    folder: Path
    tables: list[Table] = field(default_factory=list)
    markdown: Path | None = None
    html: Path | None = None
    table_files: list[Path] = field(default_factory=list)
    score_files: list[Path] = field(default_factory=list)
    plots: list[Path] = field(default_factory=list)


def _runs_markdown(runs: Sequence[ScoredRun]) -> str:
    lines = []
    for run in runs:
        role = " (reference plans, not ranked)" if run.is_reference else ""
        runtime = describe_runtimes(run.header.runtimes)
        lines.append(
            f"- {markdown_text(run.label)}{role}: run directory `{markdown_text(run.run_dir.name)}`, "
            f"{run.scores.n_episodes} episodes, {run.coverage.describe()}"
            + (f", computed on {markdown_text(runtime)}" if runtime else "")
        )
    return "\n".join(lines)


def write_report(
    runs: Sequence[ScoredRun],
    out: Path,
    *,
    reference_strategy: str = "CARE",
    plots: bool = True,
    paper: bool = True,
    extra_tables: Sequence[Table] = (),
    viewer: str | None = None,
) -> ReportFiles:
    """Write `out/report.md`, `out/report.html` (self-contained, figures embedded),
    `out/tables/<name>.{md,csv,json}`, `out/scores/<run>.json` and `out/plots/*.png`. `extra_tables` follow
    the paper's (the human error labels); `viewer` links both pages to the episode viewer; `paper` sets the
    paper's own figures (other models, marked as such) beside ours, and in the retention figure."""
    files = ReportFiles(out, [*all_tables(runs, reference_strategy, paper=paper), *extra_tables])
    (out / "tables").mkdir(parents=True, exist_ok=True)
    (out / "scores").mkdir(parents=True, exist_ok=True)
    for table in files.tables:
        for suffix, text in ((".md", table.to_markdown()), (".csv", table.to_csv()), (".json", table.to_json())):
            path = out / "tables" / f"{table.name}{suffix}"
            path.write_text(text, encoding="utf-8")
            files.table_files.append(path)
    for run, stem in zip(runs, unique_stems([r.label for r in runs]), strict=True):
        path = out / "scores" / f"{stem}.json"
        record = {
            "run": run.label,
            "run_dir": run.run_dir.name,
            "reference": run.is_reference,
            "coverage": run.coverage.to_json(),
            "header": public_header(run.header),
            **run.scores.to_json(),
        }
        path.write_text(json.dumps(record, indent=2, ensure_ascii=False) + "\n", encoding="utf-8")
        files.score_files.append(path)
    figures = []
    if plots:
        from talkdem.report.plots import write_plots

        figures = write_plots(runs, out / "plots", paper=paper)
        files.plots = [f.path for f in figures]
    body = "\n".join(t.to_markdown() for t in files.tables)
    links = "\n".join(
        f"### {markdown_text(f.title)}\n\n![{markdown_text(f.title)}](plots/{f.path.name})\n\n"
        f"{markdown_text(f.caption)}\n"
        for f in figures
    )
    figures_md = f"\n## Figures\n\n{links}" if figures else ""
    files.markdown = out / "report.md"
    browse = f" Every episode: [the viewer]({viewer.replace(' ', '%20').replace(')', '%29')})." if viewer else ""
    files.markdown.write_text(
        f"# TALK-Dem report\n\nRuns:\n{_runs_markdown(runs)}\n\nThe same report with the figures inline: "
        f"[report.html](report.html).{browse}\n\n{body}{figures_md}",
        encoding="utf-8",
    )
    from talkdem.report.html import render_report_html

    files.html = out / "report.html"
    files.html.write_text(render_report_html(runs, files.tables, figures, viewer=viewer), encoding="utf-8")
    return files
