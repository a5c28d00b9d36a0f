"""Leaderboard files: one results JSON per run in a stable schema, and a static HTML ranking page.

The results file follows the shape Hub-hosted leaderboards ingest (`config` describing the run,
`results` mapping a task name to its metrics), versioned by `schema`:

    {"schema": "talkdem-results/1",
     "config": {"model_name", "model_revision", "model_backend", "planner", "strategy", "prompt_version",
                "dataset_hash", "code_revision", "run_dir"},
     "results": {"talkdem": {"clean_sr", "average_sr", "average_retention", "hazard_cases",
                             "hazard_rate", "n_episodes", "n_tasks"},
                 "talkdem_<pattern>": {"sr", "sr_change", "sr_change_p", "retention"}, ...}}

Rates are percentages rounded to 0.01; undefined values are null. The HTML page needs no server and
loads no external asset (inline CSS, inline script for column sorting).
"""

from __future__ import annotations

import html
import json
import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from talkdem.instructions import PATTERN_CONFIGS
from talkdem.report.runs import ScoredRun, slug

__all__ = ["RESULTS_SCHEMA", "render_html", "results_record", "write_leaderboard"]

RESULTS_SCHEMA = "talkdem-results/1"


def _pct(value: float | None) -> float | None:
    return None if value is None or math.isnan(value) else round(100 * value, 2)


def results_record(run: ScoredRun) -> dict[str, Any]:
    """The stable results record of one scored run."""
    s, header = run.scores, run.header
    pattern_episodes = sum(1 for e in s.episodes if e.condition.pattern != "clean")
    retention = s.retention or {}
    results: dict[str, dict[str, Any]] = {
        "talkdem": {
            "clean_sr": _pct(s.success_rate["clean"]),
            "average_sr": _pct(s.success_rate["average"]),
            "average_retention": _pct(retention.get("average")),
            "hazard_cases": s.hazards.total_cases,
            "hazard_rate": _pct(s.hazards.total_cases / pattern_episodes) if pattern_episodes else None,
            "n_episodes": s.n_episodes,
            "n_tasks": s.n_tasks,
        }
    }
    for pattern in PATTERN_CONFIGS:
        p_value = s.sr_change_test[pattern].p_value
        results[f"talkdem_{pattern}"] = {
            "sr": _pct(s.success_rate[pattern]),
            "sr_change": _pct(s.sr_change[pattern]),
            "sr_change_p": None if math.isnan(p_value) else p_value,
            "retention": _pct(retention.get(pattern)),
        }
    return {
        "schema": RESULTS_SCHEMA,
        "config": {
            "model_name": header.model.get("name", ""),
            "model_revision": header.model.get("revision", ""),
            "model_backend": header.model.get("backend", ""),
            "planner": header.planner,
            "strategy": header.strategy,
            "prompt_version": header.prompt_version,
            "dataset_hash": header.dataset_hash,
            "code_revision": header.code_revision,
            "run_dir": str(run.run_dir),
        },
        "results": results,
    }


_COLUMNS = (
    ("Model", "model_name"),
    ("Strategy", "strategy"),
    ("Clean SR", "clean_sr"),
    ("Average SR", "average_sr"),
    ("Average retention", "average_retention"),
    ("Hazard cases", "hazard_cases"),
    ("Episodes", "n_episodes"),
)

_STYLE = """
body{font-family:system-ui,-apple-system,Segoe UI,Roboto,sans-serif;margin:2rem;color:#222}
table{border-collapse:collapse;min-width:60%}th,td{padding:.4rem .8rem;border-bottom:1px solid #ddd}
th{cursor:pointer;background:#f3f3f3;text-align:left}td.num{text-align:right;font-variant-numeric:tabular-nums}
caption{caption-side:bottom;text-align:left;color:#555;padding-top:.6rem;font-size:.9rem}
"""

_SCRIPT = """
document.querySelectorAll('th').forEach(function(th, col){th.addEventListener('click', function(){
  var body = th.closest('table').tBodies[0], rows = Array.from(body.rows);
  var asc = th.dataset.asc !== '1'; th.dataset.asc = asc ? '1' : '0';
  rows.sort(function(a, b){var x = a.cells[col].dataset.v, y = b.cells[col].dataset.v;
    var nx = parseFloat(x), ny = parseFloat(y);
    var r = (!isNaN(nx) && !isNaN(ny)) ? nx - ny : x.localeCompare(y); return asc ? r : -r;});
  rows.forEach(function(r){body.appendChild(r);});});});
"""


def _value(record: dict[str, Any], key: str) -> Any:
    if key in record["config"]:
        return record["config"][key]
    return record["results"]["talkdem"][key]


def render_html(records: Sequence[dict[str, Any]], title: str = "TALK-Dem leaderboard") -> str:
    """A self-contained page ranking runs by average SR, then average retention, then clean SR."""

    def key(record: dict[str, Any]) -> tuple[float, float, float]:
        main = record["results"]["talkdem"]

        def score(name: str) -> float:
            return -float(main[name] if main[name] is not None else -1.0)

        return score("average_sr"), score("average_retention"), score("clean_sr")

    ranked = sorted(records, key=key)
    head = "".join(f"<th>{html.escape(name)}</th>" for name in ("Rank", *(c for c, _ in _COLUMNS)))
    lines = []
    for rank, record in enumerate(ranked, start=1):
        cells = [f'<td class="num" data-v="{rank}">{rank}</td>']
        for _, field_name in _COLUMNS:
            value = _value(record, field_name)
            shown = "–" if value is None else (f"{value:.1f}" if isinstance(value, float) else str(value))
            numeric = isinstance(value, int | float)
            data = html.escape(str(value if value is not None else ""), quote=True)
            cells.append(f'<td{" class=num" if numeric else ""} data-v="{data}">{html.escape(shown)}</td>')
        lines.append("<tr>" + "".join(cells) + "</tr>")
    caption = (
        "Rates in %. Average SR: mean over the 15 pattern x level conditions; average retention: share of "
        "clean-solved tasks also solved, mean over the 15 conditions; hazard cases: pattern episodes with a "
        "safety-relevant event absent under the clean instruction. Click a heading to sort."
    )
    return (
        '<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
        f"<title>{html.escape(title)}</title><style>{_STYLE}</style></head><body>"
        f"<h1>{html.escape(title)}</h1><table><caption>{html.escape(caption)}</caption>"
        f"<thead><tr>{head}</tr></thead><tbody>{''.join(lines)}</tbody></table>"
        f"<script>{_SCRIPT}</script></body></html>\n"
    )


def write_leaderboard(runs: Sequence[ScoredRun], out: Path) -> list[Path]:
    """`out/results/<run>.json` per run, `out/leaderboard.json` (all records) and `out/index.html`."""
    (out / "results").mkdir(parents=True, exist_ok=True)
    written = []
    records = []
    for run in runs:
        record = results_record(run)
        records.append(record)
        path = out / "results" / f"{slug(run.label)}.json"
        path.write_text(json.dumps(record, indent=2, ensure_ascii=False) + "\n", encoding="utf-8")
        written.append(path)
    (out / "leaderboard.json").write_text(json.dumps(records, indent=2, ensure_ascii=False) + "\n", encoding="utf-8")
    (out / "index.html").write_text(render_html(records), encoding="utf-8")
    return [*written, out / "leaderboard.json", out / "index.html"]
