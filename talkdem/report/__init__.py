"""Paper-style reports of scored runs: tables (Markdown, CSV, JSON) and figures (PNG).

from talkdem.report import score_runs, write_report
runs = score_runs([Path("runs/vanilla"), Path("runs/care")])
written = write_report(runs, Path("report"))
"""

from talkdem.report.runs import STRATEGY_LABELS, ScoredRun, score_runs, slug, strategy_label
from talkdem.report.tables import (
    PATTERN_CODES,
    PATTERN_LABELS,
    Table,
    all_tables,
    error_table,
    hazard_table,
    plan_length_table,
    retention_table,
    strategy_retention_table,
    strategy_success_tables,
    success_table,
)
from talkdem.report.write import ReportFiles, write_report

__all__ = [
    "PATTERN_CODES",
    "PATTERN_LABELS",
    "STRATEGY_LABELS",
    "ReportFiles",
    "ScoredRun",
    "Table",
    "all_tables",
    "error_table",
    "hazard_table",
    "plan_length_table",
    "retention_table",
    "score_runs",
    "slug",
    "strategy_label",
    "strategy_retention_table",
    "strategy_success_tables",
    "success_table",
    "write_report",
]
