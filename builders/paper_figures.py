"""Extract the paper's results tables from its LaTeX source into `talkdem/report/paper_reported.json`.

The report prints the paper's figures beside ours (labelled as the paper's, other models). Reading them
from the paper's own source, by table label, keeps every printed figure traceable to one table and cell and
spares a hand transcription. Only the tables whose layout the report mirrors are taken (`TABLES`).

Run: `python -m builders.paper_figures [--paper PATH] [--out PATH]`.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import re
import sys
from dataclasses import asdict
from pathlib import Path

from talkdem.paths import repo_root
from talkdem.report.paper import PAPER_TABLES, PaperTable

__all__ = ["TABLES", "PaperTableError", "default_paper", "extract_tables", "main", "parse_tabular"]

TABLES = PAPER_TABLES
"""The paper's labels of the tables the report sets beside its own (declared where they are read)."""

FORMAT = 1


class PaperTableError(ValueError):
    """The LaTeX source lacks a table, or a table's layout is not the one this parser reads."""


def default_paper() -> Path:
    return repo_root().parent / "shared" / "paper" / "talk-dem-paper.tex"


_BRACED = r"\{((?:[^{}]|\{(?:[^{}]|\{[^{}]*\})*\})*)\}"


def _unbroken(text: str) -> str:
    """A \\shortstack's lines joined: a break after a hyphen joins the word (`Llama-3.1-` + `8B`)."""
    return re.sub(r"\s*\\\\\s*", " ", re.sub(r"-(\}?)\s*\\\\\s*", r"-\1", text))


def _plain(cell: str) -> str:
    """A cell's text: markup dropped, `$^{***}$` and `***` both as `***`, `--` as the en dash."""
    text = re.sub(r"\\shortstack(?:\[[a-z]\])?" + _BRACED, lambda m: _unbroken(m.group(1)), cell)
    text = re.sub(r"\\multirow\{[^}]*\}\{[^}]*\}" + _BRACED, r"\1", text)
    text = re.sub(r"\\(?:textbf|textit|emph|mathbf)" + _BRACED, r"\1", text)
    text = re.sub(r"\$\^\{(\**)\}\$", r"\1", text)
    text = re.sub(r"\$([^$]*)\$", r"\1", text)
    text = text.replace("\\Delta", "Δ").replace("--", "–").replace("\\%", "%").replace("{", "").replace("}", "")
    return " ".join(text.split())


def _cells(row: str) -> list[str]:
    cells: list[str] = []
    for cell in row.split("&"):
        spanned = re.fullmatch(r"\s*\\multicolumn\{(\d+)\}\{[^}]*\}" + _BRACED + r"\s*", cell)
        if spanned:
            cells += [_plain(spanned.group(2))] + [""] * (int(spanned.group(1)) - 1)
        else:
            cells.append(_plain(cell))
    return cells


def parse_tabular(body: str, label: str) -> tuple[tuple[str, ...], tuple[tuple[str, ...], ...]]:
    """Header and body rows of one `tabular` body (between `\\begin{tabular}{...}` and `\\end{tabular}`)."""
    # `\\` inside a \shortstack is a line break in a header cell, not a row end: flatten those first.
    body = re.sub(r"\\shortstack(?:\[[a-z]\])?" + _BRACED, lambda m: "{" + _unbroken(m.group(1)) + "}", body)
    body = re.sub(r"(?m)%.*$", "", body)
    body = re.sub(r"\\(?:toprule|midrule|bottomrule|hline)", "", body)
    lines = [r.strip() for r in body.split("\\\\") if r.strip()]
    if len(lines) < 2:
        raise PaperTableError(f"{label}: expected a header row and body rows in its tabular, found {len(lines)} rows")
    columns = tuple(_cells(lines[0]))
    rows: list[tuple[str, ...]] = []
    spans: dict[int, tuple[str, int]] = {}  # column -> (label, rows still covered) of an open \multirow
    for line in lines[1:]:
        cells = _cells(line)
        raw = line.split("&")
        for column, cell in enumerate(raw):
            opened = re.search(r"\\multirow\{(\d+)\}", cell)
            if opened:
                spans[column] = (cells[column], int(opened.group(1)))
        for column, (text, left) in list(spans.items()):
            if column < len(cells) and not cells[column]:
                cells[column] = text
            spans[column] = (text, left - 1)
            if left - 1 <= 0:
                del spans[column]
        if len(cells) != len(columns):
            raise PaperTableError(
                f"{label}: a row has {len(cells)} cells where the header has {len(columns)}: {line[:60]!r}"
            )
        rows.append(tuple(cells))
    return columns, tuple(rows)


def extract_tables(tex: str, labels: tuple[str, ...] = TABLES) -> list[PaperTable]:
    """Each labelled table's first `tabular` after its `\\label` (the paper puts the label before it)."""
    tables = []
    for label in labels:
        at = tex.find(f"\\label{{{label}}}")
        if at < 0:
            raise PaperTableError(f"the paper has no \\label{{{label}}}")
        start = tex.find("\\begin{tabular}", at)
        end = tex.find("\\end{tabular}", start)
        if start < 0 or end < 0:
            raise PaperTableError(f"{label}: no tabular after the label")
        spec = re.match(r"\\begin\{tabular\}\{[^}]*\}", tex[start:])
        assert spec is not None  # found just above
        columns, rows = parse_tabular(tex[start + spec.end() : end], label)
        caption = _caption(tex, at)
        tables.append(PaperTable(label, caption, columns, rows))
    return tables


def _caption(tex: str, label_at: int) -> str:
    """The caption nearest before the label, within the same table environment."""
    begin = tex.rfind("\\begin{table}", 0, label_at)
    caption = re.compile(r"\\caption" + _BRACED)
    found = caption.search(tex[begin:label_at]) or caption.search(tex[label_at : label_at + 3000])
    text = _plain(found.group(1)) if found else ""
    return text.split(". ")[0].rstrip(".") + "." if text else ""


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m builders.paper_figures", description=__doc__.splitlines()[0])
    parser.add_argument("--paper", type=Path, default=None, help="the paper's LaTeX source")
    parser.add_argument(
        "--out", type=Path, default=None, help="default: the shipped talkdem/report/paper_reported.json"
    )
    args = parser.parse_args(argv)
    paper = args.paper or default_paper()
    out = args.out or repo_root() / "talkdem" / "report" / "paper_reported.json"
    try:
        source = paper.read_bytes()
        tables = extract_tables(source.decode("utf-8"))
    except OSError as error:
        print(f"error: cannot read the paper {paper}: {error.strerror}", file=sys.stderr)
        return 1
    except PaperTableError as error:
        print(f"error: {paper}: {error}", file=sys.stderr)
        return 1
    record = {
        "format": FORMAT,
        "source": {"file": paper.name, "sha256": hashlib.sha256(source).hexdigest()},
        "tables": [asdict(t) for t in tables],
    }
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(record, indent=1, ensure_ascii=False) + "\n", encoding="utf-8")
    print(f"wrote {len(tables)} tables to {out.name}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
