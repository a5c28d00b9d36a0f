"""`talkdem markers`: markers per pattern and level on the shipped data, the paper's directions, the card."""

from __future__ import annotations

import json
from collections.abc import Sequence
from itertools import pairwise
from pathlib import Path
from typing import Any

from builders.markers.measures import MARKERS, PIPELINE, Markers, load_pipeline, text_markers
from builders.markers.measures import relevance as sentence_relevance
from builders.markers.paper import LEVEL_KEYS, PAPER, within

__all__ = ["DIRECTIONS", "compare_dementiabank", "compute_cells", "compute_variety", "directions", "run_markers"]

DIRECTIONS: tuple[tuple[str, str, int], ...] = (
    ("repair_rate", "object_substitution", +1),
    ("mtld", "object_substitution", -1),
    ("vague_reference_share", "referential_imprecision", +1),
    ("specific_noun_rate", "referential_imprecision", -1),
    ("pronoun_share", "referential_imprecision", +1),
    ("pronoun_share", "empty_speech", +1),
    ("noun_rate", "empty_speech", -1),
    ("discourse_markers", "empty_speech", +1),
    ("parse_depth", "intrusion", -1),
    ("relevance", "topic_drift", -1),
    ("relevance", "intrusion", -1),
)
"""(marker, pattern, sign): the paper's Table "Comparison of linguistic markers", direction of the dementia shift."""


_RELEVANCE_PATTERNS = frozenset(pattern for marker, pattern, _ in DIRECTIONS if marker == "relevance")


def _markers_of(texts: Sequence[str], references: Sequence[str] | None) -> list[Markers]:
    nlp = load_pipeline()
    values = [text_markers(doc) for doc in nlp.pipe(texts, batch_size=256)]
    if references is not None:
        for row, cosine in zip(values, sentence_relevance(texts, references), strict=True):
            row["relevance"] = cosine
    return values


def _mean(rows: Sequence[Markers], marker: str) -> float:
    return sum(r[marker] for r in rows) / len(rows)


def compute_cells(data: Path, relevance: bool = True) -> dict[str, dict[str, list[Markers]]]:
    """Per-instruction markers: cells["clean"]["0"], cells[pattern]["1".."3"]."""
    import pyarrow.parquet as pq

    import talk_dem

    cells: dict[str, dict[str, list[Markers]]] = {}
    clean = pq.read_table(data / "clean" / "test.parquet", columns=["instruction", "seed_instruction"]).to_pylist()
    refs = [r["seed_instruction"] for r in clean] if relevance else None
    cells["clean"] = {"0": _markers_of([r["instruction"] for r in clean], refs)}
    for pattern in talk_dem.PATTERNS:
        cells[pattern] = {}
        for level in talk_dem.LEVELS:
            path = data / pattern / f"{talk_dem.split_name(level)}.parquet"
            rows = pq.read_table(path, columns=["instruction", "seed_instruction"]).to_pylist()
            # relevance only where the paper reports it: the sentence encoder is the slow part
            refs = [r["seed_instruction"] for r in rows] if relevance and pattern in _RELEVANCE_PATTERNS else None
            cells[pattern][str(level)] = _markers_of([r["instruction"] for r in rows], refs)
    return cells


def directions(cells: dict[str, dict[str, list[Markers]]]) -> list[dict[str, Any]]:
    """For each (marker, pattern) of the paper: clean, L1, L2, L3 means and whether they move monotonically."""
    import talk_dem

    out = []
    for marker, pattern, sign in DIRECTIONS:
        if marker not in cells["clean"]["0"][0]:
            continue
        values = {"clean": _mean(cells["clean"]["0"], marker)}
        values.update({lvl: _mean(cells[pattern][lvl], marker) for lvl in ("1", "2", "3")})
        chain = [values[k] for k in LEVEL_KEYS]
        holds = all(sign * (b - a) > 0 for a, b in pairwise(chain))
        paper = dict(zip(LEVEL_KEYS, PAPER[(marker, pattern)], strict=True))
        out.append(
            {
                "marker": marker,
                "marker_label": MARKERS[marker],
                "pattern": pattern,
                "pattern_abbreviation": talk_dem.PATTERNS[pattern].abbreviation,
                "direction": sign,
                "values": values,
                "holds": holds,
                "paper": paper,
                "within_tolerance": {k: within(marker, paper[k], values[k]) for k in LEVEL_KEYS},
            }
        )
    return out


def compare_dementiabank(
    chat_dir: Path, level3: dict[str, list[Markers]], reference_text: str | None = None
) -> list[dict[str, Any]]:
    """The paper's DementiaBank comparison: per marker, Ctrl/Dem means, Cohen's d, U test, and Delta W of L3."""
    from builders.markers.chat import read_chat_folder
    from builders.markers.stats import cohens_d, delta_w_l3, mann_whitney

    groups = read_chat_folder(chat_dir)
    nlp = load_pipeline()
    values: dict[str, list[Markers]] = {}
    for group, chunks in groups.items():
        docs = nlp.pipe([c.text for c in chunks], batch_size=256)
        values[group] = [text_markers(doc, repairs=c.repairs) for doc, c in zip(docs, chunks, strict=True)]
        if reference_text:
            cosines = sentence_relevance([c.text for c in chunks], [reference_text] * len(chunks))
            for row, cosine in zip(values[group], cosines, strict=True):
                row["relevance"] = cosine
    out = []
    for marker, pattern, _ in DIRECTIONS:
        if marker not in values["control"][0] or marker not in level3[pattern][0]:
            continue
        dem = [v[marker] for v in values["dementia"]]
        ctrl = [v[marker] for v in values["control"]]
        u, p = mann_whitney(dem, ctrl)
        out.append(
            {
                "marker": marker,
                "pattern": pattern,
                "control_mean": sum(ctrl) / len(ctrl),
                "dementia_mean": sum(dem) / len(dem),
                "cohens_d": cohens_d(dem, ctrl),
                "mann_whitney_u": u,
                "p_value": p,
                "significant": p < 0.05,
                "delta_w_l3": delta_w_l3([v[marker] for v in level3[pattern]], ctrl, dem),
                "chunks": {"dementia": len(dem), "control": len(ctrl)},
            }
        )
    return out


def compute_variety(data: Path) -> dict[str, dict[str, dict[str, Any]]]:
    """Variety figures (`builders.markers.variety`) per pattern and level of the shipped benchmark."""
    import pyarrow.parquet as pq

    import talk_dem
    from builders.markers.variety import cell_variety

    out: dict[str, dict[str, dict[str, Any]]] = {}
    for pattern in talk_dem.PATTERNS:
        out[pattern] = {}
        for level in talk_dem.LEVELS:
            path = data / pattern / f"{talk_dem.split_name(level)}.parquet"
            rows = pq.read_table(path, columns=["instruction", "clean_instruction"]).to_pylist()
            out[pattern][str(level)] = cell_variety([(r["instruction"], r["clean_instruction"]) for r in rows])
    return out


def run_markers(
    data: Path | None = None,
    *,
    relevance: bool = True,
    chat_dir: Path | None = None,
    reference_text: str | None = None,
    write: bool = True,
) -> dict[str, Any]:
    """Compute the markers, write `markers.json` and refresh the card (`README.md`, `dataset_card.md`)."""
    from importlib.metadata import version

    from builders.card import markers_table, write_card
    from talkdem.paths import data_dir

    folder = Path(data) if data else data_dir()
    cells = compute_cells(folder, relevance)
    means = {
        pattern: {lvl: {m: _mean(rows, m) for m in rows[0]} for lvl, rows in levels.items()}
        for pattern, levels in cells.items()
    }
    report: dict[str, Any] = {
        "spacy_version": version("spacy"),
        "pipeline": PIPELINE,
        "relevance_encoder": "sentence-transformers/all-MiniLM-L6-v2" if relevance else None,
        "means": means,
        "directions": directions(cells),
        "variety": compute_variety(folder),
    }
    if chat_dir is not None:
        level3 = {p: cells[p]["3"] for p in cells if p != "clean"}
        report["dementiabank"] = compare_dementiabank(chat_dir, level3, reference_text)
    report["table"] = markers_table(report)
    if write:
        stored = {k: v for k, v in report.items() if k != "table"}
        (folder / "markers.json").write_text(json.dumps(stored, indent=2) + "\n")
        (folder / "markers.md").write_text(report["table"] + "\n")
        stats_file = folder / "build_stats.json"
        if stats_file.is_file():
            write_card(folder, json.loads(stats_file.read_text()))
    return report
