"""The paper's own figures beside ours: its results tables, read from `paper_reported.json`.

`builders/paper_figures.py` extracts that file from the paper's LaTeX source, by table label; nothing here is
typed in by hand. `beside_paper` adds the paper's rows (or columns) to the report's tables of the same
layout, each marked `(paper)`, and says in the caption what they are: other and larger models (six
open-weight 7B-72B models and two closed ones) on the paper's 300 tasks and its own dataset build. They are
printed for direction and ordering; they are not results of this package and not a target to match.
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from functools import cache
from pathlib import Path

from talkdem.report.table import HAZARD_LABELS, PATTERN_LABELS, Table
from talkdem.schema import LEVELS, PATTERN_CONFIGS

__all__ = [
    "MITIGATION_TABLES",
    "OPEN_WEIGHT_MODELS",
    "PAPER_MARK",
    "PAPER_TABLES",
    "PaperFigures",
    "PaperTable",
    "beside_paper",
    "load_paper_figures",
    "paper_retention_means",
    "paper_strategy_table",
]

PAPER_MARK = " (paper)"
"""Appended to every row or column label that holds the paper's figures."""

_FILE = Path(__file__).with_name("paper_reported.json")

MITIGATION_TABLES = (
    "tab:mitigation_llama8b",
    "tab:mitigation_llama70b",
    "tab:mitigation_qwen7b",
    "tab:mitigation_qwen72b",
    "tab:mitigation_gemma9b",
    "tab:mitigation_ministral8b",
)
"""The paper's per-model strategy tables, one per open-weight model."""
PAPER_TABLES = (
    "app:benchmark_results",
    "app:intensity_results",
    *MITIGATION_TABLES,
    "tab:mitigation_retention_model",
    "tab:mitigation_retention_pattern",
    "tab:plan_length",
    "tab:error_by_pattern",
    "tab:hazard_cat",
)
"""The labels of the paper's tables this module sets beside ours (what `builders/paper_figures.py` extracts)."""
OPEN_WEIGHT_MODELS = len(MITIGATION_TABLES)
"""The paper's mitigation experiments ran on six open-weight models (one table each)."""

_WHO = (
    "Rows or columns marked (paper) are the paper's figures (its table {label}) for other, larger models on its "
    "300 tasks and its own dataset build: set beside ours for direction and ordering, not as results of this "
    "package."
)


@dataclass(frozen=True)
class PaperTable:
    """One of the paper's tables as it prints it: cells as plain text, stars kept, markup gone
    (`builders/paper_figures.py` makes them from the LaTeX source)."""

    label: str
    """The paper's `\\label`."""
    caption: str
    """The caption's first sentence."""
    columns: tuple[str, ...]
    rows: tuple[tuple[str, ...], ...]
    """Body rows; a cell a `\\multirow` spans carries its label down."""

    def row(self, *keys: str) -> tuple[str, ...] | None:
        """The first row whose leading cells equal `keys` (compared as `_key` does)."""
        for row in self.rows:
            if all(_key(cell) == _key(key) for cell, key in zip(row, keys, strict=False)):
                return row
        return None

    def column(self, name: str) -> int | None:
        wanted = _key(name)
        return next((i for i, c in enumerate(self.columns) if _key(c) == wanted), None)


@dataclass(frozen=True)
class PaperFigures:
    """The paper's tables by label, with the hash of the LaTeX source they came from."""

    source_sha256: str
    tables: dict[str, PaperTable]

    def table(self, label: str) -> PaperTable:
        return self.tables[label]


def _key(text: str) -> str:
    """Labels compared without case, spaces or punctuation (`gemini-3.8 flash` = `gemini-3.8-flash`)."""
    return re.sub(r"[^a-z0-9]", "", text.lower())


@cache
def load_paper_figures(path: Path = _FILE) -> PaperFigures:
    """Read the extracted tables (shipped with the package)."""
    record = json.loads(path.read_text(encoding="utf-8"))
    tables = {
        t["label"]: PaperTable(t["label"], t["caption"], tuple(t["columns"]), tuple(tuple(r) for r in t["rows"]))
        for t in record["tables"]
    }
    return PaperFigures(record["source"]["sha256"], tables)


def _number(cell: str) -> float:
    """A printed figure without its stars or thousands commas; NaN for a dash."""
    text = cell.replace(",", "").rstrip("*").strip()
    try:
        return float(text)
    except ValueError:
        return math.nan


def _marked(name: str) -> str:
    return name + PAPER_MARK


def _with(table: Table, *, rows: Sequence[tuple[str, ...]] = (), label: str, note: str = "") -> Table:
    caption = f"{table.caption} {_WHO.format(label=label)}" + (f" {note}" if note else "")
    return replace(table, rows=(*table.rows, *rows), caption=caption)


def _success(table: Table, paper: PaperFigures) -> Table:
    source = paper.table("app:benchmark_results")
    rows = []
    for row in source.rows:
        changes = row[2:]  # F1..F5 are the patterns in the order of PATTERN_CONFIGS
        padding = ("–",) * (len(table.columns) - 4 - len(changes))
        rows.append((_marked(row[0]), "Vanilla", "4,800", row[1], *changes, *padding))
    return _with(table, rows=rows, label=source.label)


def _retention(table: Table, paper: PaperFigures) -> Table:
    source = paper.table("app:intensity_results")
    models = source.columns[2:]
    columns = (*table.columns, *(_marked(m) for m in models))
    rows = []
    pattern = ""  # our table names a pattern on its level-1 row only (the renderer spans it down)
    for ours in table.rows:
        pattern = ours[0] or pattern
        if ours[0].startswith("Successful clean tasks"):
            found: tuple[str, ...] | None = source.rows[0]
        elif ours[0] == "Average":
            found = None  # the paper prints no average row
        else:
            found = source.row(pattern, ours[1])
        rows.append((*ours, *(found[2:] if found else ("–",) * len(models))))
    caption = f"{table.caption} {_WHO.format(label=source.label)}"
    return replace(table, columns=columns, rows=tuple(rows), caption=caption)


def _strategy_cells(source: PaperTable, row: tuple[str, ...], strategies: Sequence[str]) -> list[str]:
    cells = []
    for strategy in strategies:
        column = source.column(strategy)
        cells.append(row[column] if column is not None else "–")
    return cells


def _strategy_retention(table: Table, paper: PaperFigures) -> Table:
    by_model = table.name.endswith("by_model")
    source = paper.table("tab:mitigation_retention_model" if by_model else "tab:mitigation_retention_pattern")
    strategies = table.columns[1:]
    rows = [(_marked(row[0]), *_strategy_cells(source, row, strategies)) for row in source.rows]
    note = "The paper's stars test each strategy against CARE over its 300 tasks; its rows are printed without bold."
    return _with(table, rows=rows, label=source.label, note=note)


def _appended(table: Table, paper: PaperFigures, label: str, note: str, name: Callable[[str], str] = str) -> Table:
    """`table` with the rows of the paper's table `label` (same columns) after its own, marked."""
    source = paper.table(label)
    rows = [(_marked(name(row[0])), *row[1:]) for row in source.rows]
    return _with(table, rows=rows, label=source.label, note=note)


def _our_hazard_label(printed: str) -> str:
    return next((label for label in HAZARD_LABELS.values() if _key(label) == _key(printed)), printed)


def _hazards(table: Table, paper: PaperFigures) -> Table:
    note = (
        "The paper's counts pool six open-weight models over 4,500 pattern episodes each; ours pool the runs "
        "shown: compare shares across categories and patterns, not counts."
    )
    return _appended(table, paper, "tab:hazard_cat", note, _our_hazard_label)


def _errors(table: Table, paper: PaperFigures) -> Table:
    note = (
        "The paper's are a human-annotated sample (three failures per model and condition, 270 in all); ours "
        "classify every such failure automatically."
    )
    return _appended(table, paper, "tab:error_by_pattern", note)


def _plan_length(table: Table, paper: PaperFigures) -> Table:
    return _appended(table, paper, "tab:plan_length", "The paper pools six open-weight models.")


def paper_strategy_table(paper: PaperFigures | None = None) -> Table:
    """The paper's success rate per condition under each strategy, averaged over its six open-weight models
    (computed here from its six per-model tables), in the layout of the report's per-model strategy tables."""
    paper = paper or load_paper_figures()
    sources = [paper.table(label) for label in MITIGATION_TABLES]
    strategies = sources[0].columns[2:]
    keys = [("Clean", "–")] + [(PATTERN_LABELS[p], f"L{level}") for p in PATTERN_CONFIGS for level in LEVELS]
    rows = []
    for pattern, level in keys:
        cells = []
        for strategy in strategies:
            values = []
            for source in sources:
                row, column = source.row(pattern, level), source.column(strategy)
                if row is not None and column is not None:
                    values.append(_number(row[column]))
            finite = [v for v in values if not math.isnan(v)]
            cells.append(f"{sum(finite) / len(finite):.2f}" if len(finite) == len(sources) else "–")
        shown = pattern if level in ("–", "L1") else ""
        rows.append((shown, level, *cells))
    labels = ", ".join(s.label for s in sources)
    return Table(
        "strategies_paper",
        "Task success rate under each strategy, mean of the paper's six open-weight models" + PAPER_MARK,
        f"Task success rate (%) per condition and strategy, the mean of the paper's six per-model tables "
        f"({labels}), computed from its printed figures. These are other, larger models (7B-72B) on the "
        "paper's 300 tasks: set beside ours for direction and ordering, not as results of this package.",
        ("Pattern", "Level", *strategies),
        tuple(rows),
    )


def paper_retention_means(paper: PaperFigures | None = None) -> dict[tuple[str, int], float]:
    """(pattern config, level) -> the paper's mean retention (%) over its six open-weight models (the black
    line of its intensity figure), from its intensity table."""
    paper = paper or load_paper_figures()
    source = paper.table("app:intensity_results")
    means = {}
    for pattern in PATTERN_CONFIGS:
        for level in LEVELS:
            row = source.row(PATTERN_LABELS[pattern], f"L{level}")
            if row is not None:
                means[(pattern, level)] = sum(_number(v) for v in row[2 : 2 + OPEN_WEIGHT_MODELS]) / OPEN_WEIGHT_MODELS
    return means


_BESIDE = {
    "success": _success,
    "retention": _retention,
    "strategy_retention_by_model": _strategy_retention,
    "strategy_retention_by_pattern": _strategy_retention,
    "hazards": _hazards,
    "errors": _errors,
    "plan_length": _plan_length,
}


def beside_paper(tables: Sequence[Table], paper: PaperFigures | None = None) -> list[Table]:
    """The report's tables with the paper's figures added where the paper has a table of that layout, and the
    paper's strategy means after our per-model strategy tables."""
    paper = paper or load_paper_figures()
    out = [_BESIDE[t.name](t, paper) if t.name in _BESIDE else t for t in tables]
    ours = [i for i, t in enumerate(out) if t.name.startswith("strategies_")]
    if ours:
        out.insert(ours[-1] + 1, paper_strategy_table(paper))
    return out
