"""The leaderboard page: a static, self-contained HTML file (inline CSS and script, no external asset).

Rendered from results records alone, so a Space can rebuild it from its results folder.
"""

from __future__ import annotations

import html
import math
from collections.abc import Sequence
from typing import Any

from talkdem import __version__
from talkdem.leaderboard.ranking import RANK_KEY, ComparableGroup, rank_records
from talkdem.report.coverage import Coverage
from talkdem.report.html import PAGE_STYLE, viewer_link
from talkdem.report.runs import strategy_label
from talkdem.report.table import PATTERN_CODES, PATTERN_LABELS
from talkdem.schema import PATTERN_CONFIGS

__all__ = ["SUBMIT_STEPS", "render_html"]

SUBMIT_STEPS = (
    (
        "Produce a run directory",
        "`talkdem run --model MODEL --strategy STRATEGY --out runs/NAME` runs the SayCan "
        "planner; plans from any other system become a run with `talkdem score PLANS.jsonl --name SYSTEM --out "
        'runs/NAME` (one JSON line per episode: `{"episode_id": ..., "plan": [...]}`).',
    ),
    (
        "Cover the whole benchmark",
        "Runs are ranked only against runs over the same episodes: for the main "
        "table, run all 300 tasks under all 16 conditions (no `--limit`, no `--conditions`).",
    ),
    (
        "Build the results file",
        "`talkdem leaderboard runs/NAME --out board` writes "
        "`board/results/<model>/results_<date>_<run id>.json` (machine paths are left out; a model file is named "
        "by its file name and sha256).",
    ),
    (
        "Open a pull request",
        "Add that results file to the results dataset of this leaderboard (or upload it "
        "with `talkdem push --leaderboard board --repo ORG/SPACE --results-repo ORG/RESULTS`); the page is rebuilt "
        "from the results files with `talkdem leaderboard --from-results RESULTS_DIR --out board`.",
    ),
)

_SCRIPT = """
document.querySelectorAll('table.board th').forEach(function(th, col){th.addEventListener('click', function(){
  var body = th.closest('table').tBodies[0], rows = Array.from(body.rows);
  var asc = th.dataset.asc !== '1'; th.dataset.asc = asc ? '1' : '0';
  rows.sort(function(a, b){var x = a.cells[col].dataset.v, y = b.cells[col].dataset.v;
    var nx = parseFloat(x), ny = parseFloat(y);
    var r = (!isNaN(nx) && !isNaN(ny)) ? nx - ny : String(x).localeCompare(String(y)); return asc ? r : -r;});
  rows.forEach(function(r){body.appendChild(r);});});});
"""

_EXTRA_STYLE = """
body{max-width:none}
table.board td,table.board th{font-size:.82rem}
table.board th{cursor:pointer}
.lead{color:#444}.warn{background:#fff6e0;border-left:4px solid #e0a800;padding:.5rem .8rem}
#rank-key{background:#eef5ff;border-left:4px solid #3c78d8;padding:.5rem .8rem}
td.rank{font-weight:700}
.prov{display:block;color:#666;font-size:.7rem;font-family:ui-monospace,monospace}
.sub{display:block;color:#666;font-size:.72rem}
table.board td,table.board th{padding:.3rem .38rem;font-size:.8rem}
table.board .ci{font-size:.68rem}
footer{margin-top:3rem;color:#777;font-size:.8rem}
ol li{margin:.4rem 0}
"""


def _pct(value: Any) -> str:
    return "–" if value is None or (isinstance(value, float) and math.isnan(value)) else f"{100 * float(value):.1f}"


def _num(value: Any, interval: Sequence[Any] | None = None, undefined: str = "undefined") -> str:
    shown = _pct(value)
    sort = "" if value is None else f"{float(value):.6f}"
    ci = ""
    title = f' title="{undefined}"' if value is None else ""
    if interval and None not in interval and value is not None:
        # Whole percents keep 13 numeric columns readable side by side; the exact bounds are in the tooltip.
        low, high = (100 * float(v) for v in interval)
        ci = f'<span class="ci">{low:.0f}–{high:.0f}</span>'
        title = f' title="95% interval {low:.1f}–{high:.1f}"'

    return f'<td class="num" data-v="{sort}"{title}>{html.escape(shown)}{ci}</td>'


def _short(value: str, digits: int = 12) -> str:
    return value[:digits] if len(value) > digits else value


def _two_lines(first: str, second: str, title: str = "") -> str:
    """A text cell with a smaller second line (the table stays narrow enough to read without scrolling)."""
    attr = f' title="{html.escape(title, quote=True)}"' if title else ""
    return (
        f'<td data-v="{html.escape(first, quote=True)}"{attr}>{html.escape(first or "–")}'
        f'<span class="sub">{html.escape(second or "–")}</span></td>'
    )


def _model(config: dict[str, Any]) -> str:
    """The model's name and, under it, the run's provenance (kept in the row so nothing needs scrolling)."""
    provenance = [
        ("rev", config["model_sha"]),
        ("date", config.get("eval_date", "")),
        ("data", config["dataset_hash"]),
        ("code", config["code_revision"]),
    ]
    shown = [f"{name} {(value if name == 'date' else _short(value, 8)) or '–'}" for name, value in provenance]
    full = "; ".join(f"{name}: {value or 'unknown'}" for name, value in provenance)
    lines = "".join(f'<span class="prov">{html.escape(" · ".join(shown[i : i + 2]))}</span>' for i in (0, 2))
    return (
        f'<td data-v="{html.escape(config["model_name"], quote=True)}" title="{html.escape(full, quote=True)}">'
        f"{html.escape(config['model_name'] or '–')}{lines}</td>"
    )


_CLARIFY_COLUMNS = [
    (
        "Asks",
        "clarification: who answered the planner's questions (oracle: clearly; in-pattern: under the "
        "instruction's own pattern and level); – for runs that could not ask",
    ),
    ("Q/ep", "clarification: questions asked per episode"),
    ("Help", "clarification: share of episodes with at least one question"),
    ("Unneeded", "clarification: questions asked on clean instructions"),
]
"""The clarification column group, shown only in a table where some run could ask."""


def _asks(records: Sequence[dict[str, Any]]) -> bool:
    return any("talkdem_clarification" in record["results"] for record in records)


def _clarify_cells(record: dict[str, Any]) -> list[str]:
    found = record["results"].get("talkdem_clarification")
    if found is None:
        return ['<td data-v="">–</td>', *['<td class="num" data-v="">–</td>'] * 3]
    mode = html.escape(str(record["config"].get("clarify", "")), quote=True)
    q = html.escape(f"{float(found['questions_per_episode']):.2f}", quote=True)
    unneeded = html.escape(str(found["unneeded_questions"]), quote=True)
    return [
        f'<td data-v="{mode}">{mode}</td>',
        f'<td class="num" data-v="{q}">{q}</td>',
        _num(found["help_rate"]),
        f'<td class="num" data-v="{unneeded}">{unneeded}</td>',
    ]


def _columns(ranked: bool, asks: bool = False) -> list[tuple[str, str]]:
    """(heading, tooltip) per column (`asks`: with the clarification group)."""
    columns = [("Rank", RANK_KEY)] if ranked else []
    columns += [
        (
            "Model",
            "model name (a weights file by its file name); under it: weights sha256 or hub revision, "
            "dataset hash, code revision, date of the run",
        ),
        (
            "Strategy",
            "prompting strategy; under it the planner (saycan: log-likelihood scoring; saycan-generative: "
            "generated steps; external: plans from another system)",
        ),
        ("Coverage", "tasks evaluated out of the benchmark's; under it the conditions run"),
        ("Avg SR", "average success rate over the 15 pattern × level conditions (the rank key)"),
        ("Avg ret.", "average clean-conditioned retention over the 15 conditions"),
        ("Clean SR", "success rate on the clean instructions"),
    ]
    for pattern in PATTERN_CONFIGS:
        code, name = PATTERN_CODES[pattern], PATTERN_LABELS[pattern]
        columns.append((f"{code} SR", f"{name}: success rate, mean over levels 1-3"))
        columns.append((f"{code} ret.", f"{name}: retention, mean over levels 1-3"))
    columns += [
        ("Hazards", "pattern episodes with a safety-relevant event absent under the clean instruction"),
    ]
    return columns + (_CLARIFY_COLUMNS if asks else [])


def _row(record: dict[str, Any], rank: int | None, asks: bool = False) -> str:
    config, main = record["config"], record["results"]["talkdem"]
    intervals = record.get("intervals", {})
    coverage = Coverage.from_json(record["coverage"])
    undefined_ret = "undefined: no task solved under clean"
    tasks, _, conditions = coverage.describe().partition(" × ")
    cells = [f'<td class="num rank" data-v="{int(rank)}">{int(rank)}</td>'] if rank is not None else []
    cells += [
        _model(config),
        _two_lines(strategy_label(config["strategy"]), config["planner"]),
        _two_lines(tasks, conditions, title=f"episode set {coverage.task_set}"),
        _num(main["average_sr"], intervals.get("average_sr"), "undefined: no pattern episode"),
        _num(main["average_retention"], intervals.get("average_retention"), undefined_ret),
        _num(main["clean_sr"], intervals.get("clean_sr"), "undefined: no clean episode"),
    ]
    for pattern in PATTERN_CONFIGS:
        found = record["results"][f"talkdem_{pattern}"]
        cells.append(_num(found["sr"], intervals.get(f"{pattern}_sr"), "undefined: pattern not run"))
        cells.append(_num(found["retention"], intervals.get(f"{pattern}_retention"), undefined_ret))
    # Escaped like every other value: a results file from elsewhere may hold anything (it is validated on
    # read, but the page does not rely on that).
    hazards = html.escape(str(main["hazard_cases"]), quote=True)
    cells += [f'<td class="num" data-v="{hazards}">{hazards}</td>']
    if asks:
        cells += _clarify_cells(record)
    return f'<tr data-run="{html.escape(record["run_id"], quote=True)}">' + "".join(cells) + "</tr>"


def _table(rows: Sequence[tuple[int | None, dict[str, Any]]], ranked: bool, table_id: str) -> str:
    asks = _asks([record for _, record in rows])
    head = "".join(
        f'<th scope="col" title="{html.escape(tip, quote=True)}">{html.escape(name)}</th>'
        for name, tip in _columns(ranked, asks)
    )
    body = "".join(_row(record, rank, asks) for rank, record in rows)
    return (
        f'<div class="scroll"><table class="board{" ranked" if ranked else ""}" id="{table_id}">'
        f"<thead><tr>{head}</tr></thead><tbody>{body}</tbody></table></div>"
    )


def _group_heading(group: ComparableGroup) -> str:
    coverage = Coverage.from_json(group.coverage)
    return (
        f"Runs over {coverage.describe()} "
        f"<small>(episode set {html.escape(group.task_set)}, dataset {html.escape(_short(group.dataset_hash))})</small>"
    )


def _inline_code(text: str) -> str:
    """Escaped text with `backticks` as <code>."""
    parts = html.escape(text).split("`")
    return "".join(f"<code>{p}</code>" if i % 2 else p for i, p in enumerate(parts))


def render_html(
    records: Sequence[dict[str, Any]], title: str = "TALK-Dem leaderboard", viewer: str | None = None
) -> str:
    """The page: one ranked table per comparable group, the reference plans apart, how to submit;
    `viewer`: a link to the episode viewer of these runs (`talkdem view`)."""
    standings = rank_records(records)
    legend = "; ".join(f"{PATTERN_CODES[p]}: {PATTERN_LABELS[p]}" for p in PATTERN_CONFIGS)
    parts = [
        f"<h1>{html.escape(title)}</h1>",
        '<p class="lead">Robot task planning under dementia-associated communication: household tasks given '
        "as clean instructions and under five communication patterns at three intensity levels, planned and "
        "executed in a symbolic AI2-THOR/ALFRED simulator.</p>",
        f'<p id="rank-key"><strong>Rank key:</strong> {html.escape(RANK_KEY)}. Runs are ranked only against runs '
        "over the same episodes of the same dataset; equal keys share a rank. Rates in %; under each value its "
        f"95% bootstrap interval over tasks, in whole percents (none when the run was scored without "
        f"resampling). {legend}.</p>",
    ]
    if viewer:
        parts.append(viewer_link(viewer))
    if len(standings.groups) > 1:
        parts.append(
            f'<p class="warn" id="not-comparable">These runs fall into {len(standings.groups)} groups that covered '
            "different episodes (or dataset versions). They are not comparable across groups: each group is "
            "ranked on its own.</p>"
        )
    for i, group in enumerate(standings.groups, start=1):
        parts.append(
            f'<section class="group" id="group-{i}"><h2>{_group_heading(group)}</h2>'
            f"{_table(group.ranked, True, f'board-{i}')}</section>"
        )
    if not standings.groups:
        parts.append('<p class="warn">No planner runs yet.</p>')
    if standings.reference:
        parts.append(
            '<section id="reference"><h2>Reference plans (oracle, not ranked)</h2><p>The tasks\' reference plans '
            "executed like any run: an upper bound that checks the simulator, not a planner.</p>"
            f"{_table([(None, r) for r in standings.reference], False, 'reference-board')}</section>"
        )
    steps = "".join(f"<li><strong>{html.escape(h)}.</strong> {_inline_code(t)}</li>" for h, t in SUBMIT_STEPS)
    parts.append(f'<section id="submit"><h2>How to submit a run</h2><ol>{steps}</ol></section>')
    parts.append(f"<footer>Built by talkdem {html.escape(__version__)} from {len(records)} results file(s).</footer>")
    return (
        '<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
        '<meta name="viewport" content="width=device-width, initial-scale=1">'
        f"<title>{html.escape(title)}</title><style>{PAGE_STYLE}{_EXTRA_STYLE}</style></head><body>"
        + "\n".join(parts)
        + f"<script>{_SCRIPT}</script></body></html>\n"
    )
