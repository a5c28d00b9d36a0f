"""One self-contained HTML page of a report: the runs, the paper-style tables and the figures (embedded
as base64 PNG), readable offline and safe to publish (every embedded string is escaped)."""

from __future__ import annotations

import base64
import html
import re
from collections.abc import Sequence

from talkdem.report.links import safe_href
from talkdem.report.plots import PlotFile
from talkdem.report.public import public_model
from talkdem.report.runs import ScoredRun
from talkdem.report.table import Table
from talkdem.runs.runtime import describe_runtimes

__all__ = ["PAGE_STYLE", "render_report_html", "table_html", "viewer_link"]

PAGE_STYLE = """
body{font-family:system-ui,-apple-system,"Segoe UI",Roboto,sans-serif;margin:2rem auto;max-width:1500px;
  padding:0 1rem;color:#1f1f1f;line-height:1.45}
h1{font-size:1.6rem}h2{font-size:1.2rem;margin-top:2.2rem;border-bottom:1px solid #ddd;padding-bottom:.2rem}
.scroll{overflow-x:auto;margin:.6rem 0}
table{border-collapse:collapse;font-size:.88rem;min-width:32rem}
th,td{padding:.3rem .6rem;border-bottom:1px solid #e2e2e2;vertical-align:top;white-space:nowrap}
th{background:#f4f4f4;text-align:left;font-weight:600}
td.num,th.num{text-align:right;font-variant-numeric:tabular-nums}
caption{caption-side:bottom;text-align:left;color:#555;padding-top:.5rem;font-size:.82rem;white-space:normal}
.ci{display:block;color:#666;font-size:.74rem}
figure{margin:1.4rem 0}figure img{max-width:100%;height:auto;display:block;border:1px solid #eee;box-sizing:border-box}
figcaption{color:#555;font-size:.85rem;margin-top:.3rem}
code{font-size:.85em}
"""

_NUMERIC = re.compile(r"^(?:\*\*)?[-+−]?(?:\d[\d,]*(?:\.\d+)?|–)(?:\*\*)?\**$")


def _cell(text: str) -> str:
    """Escaped text with the tables' one piece of Markdown, `**bold**`, kept."""
    escaped = html.escape(text)
    return re.sub(r"\*\*(.+?)\*\*", r"<strong>\1</strong>", escaped)


def table_html(table: Table) -> str:
    """A paper-style table: numeric columns right-aligned; a blank label cell joins the label beside it
    (colspan) or above it (rowspan), as the paper prints grouped rows."""
    width = len(table.columns)
    numeric = [
        i > 0 and all(_NUMERIC.match(r[i]) for r in table.rows if i < len(r) and r[i] != "") for i in range(width)
    ]
    grid: list[list[tuple[str, int, int] | None]] = [[(c, 1, 1) for c in row] for row in table.rows]
    for row in grid:  # ("Average", "") -> one cell over both label columns
        for i in range(width - 1, 0, -1):
            cell, left = row[i], row[i - 1]
            if cell is not None and left is not None and cell[0] == "" and not numeric[i] and left[0] != "":
                row[i - 1] = (left[0], 1, left[2] + cell[2])
                row[i] = None
    for r in range(1, len(grid)):  # a blank first cell continues the group above
        cell = grid[r][0]
        if cell is not None and cell[0] == "" and cell[2] == 1:
            for above in range(r - 1, -1, -1):
                found = grid[above][0]
                if found is not None:
                    if found[2] == 1 and found[0] != "":
                        grid[above][0] = (found[0], found[1] + 1, 1)
                        grid[r][0] = None
                    break
    head = "".join(
        f'<th{" class=num" if numeric[i] else ""} scope="col">{html.escape(c)}</th>'
        for i, c in enumerate(table.columns)
    )
    body = []
    for row in grid:
        cells = []
        for i, cell in enumerate(row):
            if cell is None:
                continue
            text, rowspan, colspan = cell
            attrs = (" class=num" if numeric[i] else "") + (f' rowspan="{rowspan}"' if rowspan > 1 else "")
            attrs += f' colspan="{colspan}"' if colspan > 1 else ""
            cells.append(f"<td{attrs}>{_cell(text) if text else '&nbsp;'}</td>")
        body.append("<tr>" + "".join(cells) + "</tr>")
    return (
        f'<div class="scroll"><table id="table-{html.escape(table.name)}">'
        f"<caption>{html.escape(table.caption)}</caption><thead><tr>{head}</tr></thead>"
        f"<tbody>{''.join(body)}</tbody></table></div>"
    )


def _runs_table(runs: Sequence[ScoredRun]) -> str:
    rows = []
    for run in runs:
        model = public_model(run.header.model)
        cells = (
            run.label + (" (reference plans, not ranked)" if run.is_reference else ""),
            model["name"] or "–",
            (model["revision"][:12] or "–"),
            run.setting,
            run.header.planner,
            run.coverage.describe(),
            f"{run.scores.n_episodes:,}",
            (run.header.created[:10] or "–"),
            (run.header.dataset_hash[:12] or "–"),
            (run.header.code_revision[:12] or "–"),
            (describe_runtimes(run.header.runtimes) or "–"),
        )
        rows.append("<tr>" + "".join(f"<td>{html.escape(c)}</td>" for c in cells) + "</tr>")
    head = (
        "Run",
        "Model",
        "Revision / file hash",
        "Strategy",
        "Planner",
        "Coverage",
        "Episodes",
        "Date",
        "Dataset",
        "Code",
        "Runtime",
    )
    return (
        '<div class="scroll"><table id="runs"><thead><tr>'
        + "".join(f"<th>{h}</th>" for h in head)
        + "</tr></thead><tbody>"
        + "".join(rows)
        + "</tbody></table></div>"
    )


def _figure(plot: PlotFile) -> str:
    data = base64.b64encode(plot.path.read_bytes()).decode("ascii")
    return (
        f'<figure><img alt="{html.escape(plot.title, quote=True)}" src="data:image/png;base64,{data}">'
        f"<figcaption><strong>{html.escape(plot.title)}.</strong> {html.escape(plot.caption)}</figcaption></figure>"
    )


def viewer_link(href: str) -> str:
    """A paragraph linking to the episode viewer (`talkdem view`); `href` is checked as a browser will read it
    (`talkdem.report.links.safe_href`: relative or http(s), never a script) and escaped."""
    href = safe_href(href)
    return (
        f'<p id="viewer-link"><a href="{html.escape(href, quote=True)}">Browse every episode</a> in the viewer: '
        "instructions, plans step by step with the simulator's feedback, and the error labelling.</p>"
    )


def render_report_html(
    runs: Sequence[ScoredRun],
    tables: Sequence[Table],
    plots: Sequence[PlotFile],
    title: str = "TALK-Dem report",
    viewer: str | None = None,
) -> str:
    """The report page: runs (with coverage and provenance), every table, every figure; `viewer`: a link
    to the episode viewer (`talkdem view`)."""
    sections = [
        f"<h1>{html.escape(title)}</h1>",
        "<p>Rates in %. Runs over different episodes (see Coverage) are not directly comparable; the reference "
        "plans are an upper bound, not a planner.</p>",
        *([viewer_link(viewer)] if viewer else []),
        "<h2>Runs</h2>",
        _runs_table(runs),
        "<h2>Tables</h2>",
    ]
    for table in tables:
        sections.append(f"<h3>{html.escape(table.title)}</h3>{table_html(table)}")
    if plots:
        sections.append("<h2>Figures</h2>")
        sections += [_figure(p) for p in plots]
    return (
        '<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
        '<meta name="viewport" content="width=device-width, initial-scale=1">'
        f"<title>{html.escape(title)}</title><style>{PAGE_STYLE}</style></head><body>"
        + "\n".join(sections)
        + "</body></html>\n"
    )
