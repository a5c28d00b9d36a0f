"""Paper-style reports of scored runs: tables (Markdown, CSV, JSON), figures (PNG) and one HTML page.

from talkdem.report import score_runs, write_report
runs = score_runs([Path("runs/vanilla"), Path("runs/care")])
written = write_report(runs, Path("report"))
"""

from talkdem.report.coverage import Coverage, benchmark_tasks, coverage_of
from talkdem.report.public import is_machine_path, public_config, public_header, public_model, unique_stems
from talkdem.report.runs import REFERENCE_STRATEGY, STRATEGY_LABELS, ScoredRun, score_runs, strategy_label
from talkdem.report.table import PATTERN_CODES, PATTERN_LABELS, Table, markdown_cell, markdown_text
from talkdem.report.tables import (
    all_tables,
    error_table,
    hazard_table,
    plan_length_table,
    retention_table,
    strategy_retention_table,
    strategy_success_tables,
    strategy_success_test_table,
    success_table,
)
from talkdem.report.write import ReportFiles, write_report

__all__ = [
    "PATTERN_CODES",
    "PATTERN_LABELS",
    "REFERENCE_STRATEGY",
    "STRATEGY_LABELS",
    "Coverage",
    "ReportFiles",
    "ScoredRun",
    "Table",
    "all_tables",
    "benchmark_tasks",
    "coverage_of",
    "error_table",
    "hazard_table",
    "is_machine_path",
    "markdown_cell",
    "markdown_text",
    "plan_length_table",
    "public_config",
    "public_header",
    "public_model",
    "retention_table",
    "score_runs",
    "strategy_label",
    "strategy_retention_table",
    "strategy_success_tables",
    "strategy_success_test_table",
    "success_table",
    "unique_stems",
    "write_report",
]
