"""`Table`, the report's unit of output, and the labels every table module shares.

A module of its own so that `tables`, `clarification`, `paper` and the other report modules build on it
without importing one another (no import cycles).
"""

from __future__ import annotations

import csv
import io
import json
import re
from collections.abc import Sequence
from dataclasses import dataclass

from talkdem.schema import PATTERNS

__all__ = ["HAZARD_LABELS", "PATTERN_CODES", "PATTERN_LABELS", "Table", "markdown_cell", "markdown_text"]

PATTERN_LABELS = {config: pattern.name for config, pattern in PATTERNS.items()}
PATTERN_CODES = {config: pattern.abbreviation for config, pattern in PATTERNS.items()}
HAZARD_LABELS = {
    "inappropriate_microwave_heating": "(i) Inappropriate microwave heating",
    "appliance_left_running": "(ii) Appliance left running",
    "unrequested_knife_use": "(iii) Unrequested knife use",
    "electronic_device_into_water": "(iv) Electronic device into water",
}


def markdown_text(text: str) -> str:
    """One line of Markdown: line breaks become spaces, and text that a renderer would take for an HTML tag
    (`<b`, `</`, `<!`) is shown instead (`p<0.05` stays as written)."""
    return " ".join(re.sub(r"<(?=[A-Za-z/!?])", "&lt;", text).split())


def markdown_cell(text: str) -> str:
    """A table cell: `markdown_text` with `|` escaped, so a run named `a|b` stays one cell."""
    return markdown_text(text).replace("|", "\\|")


@dataclass(frozen=True)
class Table:
    """A titled table of display strings; `name` is its file stem."""

    name: str
    title: str
    caption: str
    columns: tuple[str, ...]
    rows: tuple[tuple[str, ...], ...]

    def to_markdown(self) -> str:
        def line(cells: Sequence[str]) -> str:
            return "| " + " | ".join(markdown_cell(c) for c in cells) + " |"

        align = ["---"] + ["---:"] * (len(self.columns) - 1)
        body = [line(self.columns), "|" + "|".join(align) + "|", *(line(r) for r in self.rows)]
        return f"### {markdown_text(self.title)}\n\n" + "\n".join(body) + f"\n\n{markdown_text(self.caption)}\n"

    def to_csv(self) -> str:
        buffer = io.StringIO()
        writer = csv.writer(buffer, lineterminator="\n")
        writer.writerow(self.columns)
        writer.writerows(self.rows)
        return buffer.getvalue()

    def to_json(self) -> str:
        record = {
            "name": self.name,
            "title": self.title,
            "caption": self.caption,
            "columns": list(self.columns),
            "rows": [list(r) for r in self.rows],
        }
        return json.dumps(record, indent=2, ensure_ascii=False) + "\n"
