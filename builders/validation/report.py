"""`talkdem validate-dataset DIR`: the independent markers, fluency and masked variety of a dataset folder.

Writes `validation.json` (every number) and `validation.md` (the tables the card shows) into the output
folder (the dataset folder by default). The "ours" column is read from the folder's `markers.json` (what
`talkdem markers` computed with the generator-side measures); nothing of `builders.markers` is imported.
"""

from __future__ import annotations

import json
import sys
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from builders.validation.dataset import CLEAN, Cell, ranking_models, read_cells
from builders.validation.paper import DIRECTIONS, LEVEL_KEYS, PAPER, moves_as_paper, within

__all__ = ["VALIDATION_VERSION", "compare_markers", "independent_markers", "run_validation"]

VALIDATION_VERSION = 1
_RELEVANCE_PATTERNS = frozenset(pattern for marker, pattern in DIRECTIONS if marker == "relevance")


def _log(message: str) -> None:
    print(f"validate-dataset: {message}", file=sys.stderr, flush=True)


def _relevance(sentences: Sequence[list[str]], references: Sequence[str]) -> list[float]:
    """Mean over each text's sentences of the sentence's cosine to the text's reference (MiniLM)."""
    from talkdem.embeddings import encode

    unique = sorted({s for parts in sentences for s in parts} | set(references))
    index = {s: i for i, s in enumerate(unique)}
    vectors = encode(unique)
    out = []
    for parts, reference in zip(sentences, references, strict=True):
        ref = vectors[index[reference]]
        out.append(float(sum(float(vectors[index[s]] @ ref) for s in parts) / len(parts)))
    return out


def independent_markers(cells: Sequence[Cell], log: Callable[[str], None] = _log) -> dict[str, dict[str, float]]:
    """Per cell key: the mean of each marker over the cell's instructions (relevance where the paper has it)."""
    from builders.validation.markers import doc_markers, sentence_texts
    from builders.validation.pipeline import load_pipeline

    nlp = load_pipeline()
    means: dict[str, dict[str, float]] = {}
    for cell in cells:
        started = time.monotonic()
        texts = [r["instruction"] for r in cell.rows]
        docs = list(nlp.pipe(texts, batch_size=128))
        values = [doc_markers(doc) for doc in docs]
        if cell.pattern == CLEAN or cell.pattern in _RELEVANCE_PATTERNS:
            sentences = [sentence_texts(doc) or [doc.text] for doc in docs]
            cosines = _relevance(sentences, [r["seed_instruction"] for r in cell.rows])
            for row, cosine in zip(values, cosines, strict=True):
                row["relevance"] = cosine
        means[cell.key] = {m: sum(v[m] for v in values) / len(values) for m in values[0]}
        log(f"markers {cell.key}: {len(texts)} instructions in {time.monotonic() - started:.0f} s")
    return means


def _ours(folder: Path) -> dict[str, dict[str, float]] | None:
    """The generator-side markers (`talkdem markers`) by cell key, when the folder has them."""
    path = folder / "markers.json"
    if not path.is_file():
        return None
    means = json.loads(path.read_text()).get("means", {})
    out: dict[str, dict[str, float]] = {}
    for pattern, levels in means.items():
        for level, values in levels.items():
            out[CLEAN if pattern == CLEAN else f"{pattern}:{level}"] = values
    return out


def compare_markers(
    independent: dict[str, dict[str, float]], ours: dict[str, dict[str, float]] | None
) -> list[dict[str, Any]]:
    """One row per (marker, pattern) of the paper's table: paper, ours and independent values, the checks."""
    rows = []
    for (marker, pattern), paper_values in PAPER.items():
        keys = [CLEAN, f"{pattern}:1", f"{pattern}:2", f"{pattern}:3"]
        paper = dict(zip(LEVEL_KEYS, paper_values, strict=True))
        sign = DIRECTIONS[(marker, pattern)]
        row: dict[str, Any] = {"marker": marker, "pattern": pattern, "direction": sign, "paper": paper}
        for column, source in (("independent", independent), ("ours", ours)):
            if source is None or any(marker not in source.get(k, {}) for k in keys):
                row[column] = None
                continue
            values = {level: source[k][marker] for level, k in zip(LEVEL_KEYS, keys, strict=True)}
            row[column] = {
                "values": values,
                "within_tolerance": {k: within(marker, paper[k], values[k]) for k in LEVEL_KEYS},
                "moves_as_paper": moves_as_paper(sign, [values[k] for k in LEVEL_KEYS]),
                "clean_to_l3_as_paper": sign * (values["3"] - values["clean"]) > 0,
            }
        rows.append(row)
    return rows


def _summary(rows: Sequence[dict[str, Any]], column: str) -> dict[str, int] | None:
    present = [r[column] for r in rows if r[column] is not None]
    if not present:
        return None
    return {
        "cells_within_tolerance": sum(sum(c["within_tolerance"].values()) for c in present),
        "cells": sum(len(c["within_tolerance"]) for c in present),
        "markers_moving_as_paper": sum(c["moves_as_paper"] for c in present),
        "markers": len(present),
    }


def _variety(cells: Sequence[Cell]) -> dict[str, dict[str, Any]]:
    from builders.validation.variety import cell_variety, masker, sentence_count_distribution, type_names

    mask = masker(type_names(r for c in cells for r in c.rows))
    out = {}
    for cell in cells:
        if cell.pattern == CLEAN:
            counts = sentence_count_distribution([r["instruction"] for r in cell.rows])
            out[cell.key] = {"sentence_counts": counts}
            continue
        out[cell.key] = cell_variety([(r["instruction"], r["clean_instruction"]) for r in cell.rows], mask)
    return out


def _fluency(cells: Sequence[Cell], cache_file: Path | None, threads: int = 1) -> dict[str, Any]:
    from builders.validation.fluency import FluencyScorer, cell_fluency, print_progress

    scorer = FluencyScorer.default(cache_file, threads)
    texts = [r["instruction"] for c in cells for r in c.rows]
    nll = scorer.nll_per_token(texts, progress=print_progress)
    by_cell, at = {}, 0
    for cell in cells:
        by_cell[cell.key] = nll[at : at + len(cell.rows)]
        at += len(cell.rows)
    clean = by_cell[CLEAN]
    return {
        "model": scorer.identity,
        "context": scorer.context,
        "cells": {key: cell_fluency(values, clean) for key, values in by_cell.items()},
    }


def run_validation(
    folder: Path,
    out: Path | None = None,
    *,
    fluency: bool = True,
    fluency_cache: Path | None = None,
    threads: int = 1,
    log: Callable[[str], None] = _log,
) -> dict[str, Any]:
    """Compute everything, write `validation.json` and `validation.md` into `out` (default: `folder`)."""
    from builders.validation.card import validation_markdown
    from builders.validation.pipeline import PIPELINE_NAME, verify_pipeline

    target = out or folder
    cells = read_cells(folder)
    versions = sorted({str(r["prompt_version"]) for c in cells for r in c.rows})
    log(f"{folder.name}: {sum(len(c.rows) for c in cells)} instructions, prompt version(s) {', '.join(versions)}")
    check = verify_pipeline()
    independent = independent_markers(cells, log)
    rows = compare_markers(independent, _ours(folder))
    log("masked variety")
    report: dict[str, Any] = {
        "validation_version": VALIDATION_VERSION,
        "prompt_versions": versions,
        "ranked_by": ranking_models(folder),
        "pipeline": {
            "name": PIPELINE_NAME,
            "official_files_checked": check.official_files,
            "observed_files_checked": check.observed_files,
        },
        "markers": {
            "means": independent,
            "table": rows,
            "independent": _summary(rows, "independent"),
            "ours": _summary(rows, "ours"),
        },
        "variety": _variety(cells),
    }
    if fluency:
        log(f"fluency (SmolLM2-135M, {threads} thread{'s' if threads > 1 else ''})")
        started = time.monotonic()  # logged, not stored: the files must not depend on the machine
        report["fluency"] = _fluency(cells, fluency_cache, threads)
        log(f"fluency: {time.monotonic() - started:.0f} s")
    target.mkdir(parents=True, exist_ok=True)
    (target / "validation.json").write_text(json.dumps(report, indent=2, sort_keys=True) + "\n")
    (target / "validation.md").write_text(validation_markdown(report) + "\n")
    return report
