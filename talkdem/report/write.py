"""Write a report folder: every table as .md/.csv/.json, report.md with all of them, scores, figures."""

from __future__ import annotations

import json
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

from talkdem.report.runs import ScoredRun, slug
from talkdem.report.tables import Table, all_tables

__all__ = ["ReportFiles", "write_report"]


@dataclass
class ReportFiles:
    """What `write_report` wrote."""

    folder: Path
    tables: list[Table] = field(default_factory=list)
    markdown: Path | None = None
    table_files: list[Path] = field(default_factory=list)
    score_files: list[Path] = field(default_factory=list)
    plots: list[Path] = field(default_factory=list)


def write_report(
    runs: Sequence[ScoredRun], out: Path, *, reference_strategy: str = "CARE", plots: bool = True
) -> ReportFiles:
    """Write `out/report.md`, `out/tables/<name>.{md,csv,json}`, `out/scores/<run>.json`, `out/plots/*.png`."""
    files = ReportFiles(out, all_tables(runs, reference_strategy))
    (out / "tables").mkdir(parents=True, exist_ok=True)
    (out / "scores").mkdir(parents=True, exist_ok=True)
    for table in files.tables:
        for suffix, text in ((".md", table.to_markdown()), (".csv", table.to_csv()), (".json", table.to_json())):
            path = out / "tables" / f"{table.name}{suffix}"
            path.write_text(text, encoding="utf-8")
            files.table_files.append(path)
    files.markdown = out / "report.md"
    runs_list = "\n".join(f"- {r.label}: `{r.run_dir}` ({r.scores.n_episodes} episodes)" for r in runs)
    body = "\n".join(t.to_markdown() for t in files.tables)
    files.markdown.write_text(f"# TALK-Dem report\n\nRuns:\n{runs_list}\n\n{body}", encoding="utf-8")
    for run in runs:
        path = out / "scores" / f"{slug(run.label)}.json"
        record = {"run": run.label, "run_dir": str(run.run_dir), "header": run.header.to_json(), **run.scores.to_json()}
        path.write_text(json.dumps(record, indent=2, ensure_ascii=False) + "\n", encoding="utf-8")
        files.score_files.append(path)
    if plots:
        from talkdem.report.plots import write_plots

        files.plots = write_plots(runs, out / "plots")
    return files
