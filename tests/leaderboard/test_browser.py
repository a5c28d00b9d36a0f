"""The leaderboard page as Chromium lays it out: what a reader sees, not only the HTML text."""

from __future__ import annotations

import itertools
import re
from pathlib import Path
from typing import Any

import pytest
from browser_helpers import distinct_colors, measure, overlaps, screenshot


@pytest.fixture(scope="module")
def seen(board: Path, tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    return measure(board / "index.html", tmp_path_factory.mktemp("chromium"))


def _tables(seen: dict[str, Any], cls: str) -> list[dict[str, Any]]:
    return [t for t in seen["tables"] if cls in t["cls"].split()]


def _column(table: dict[str, Any], name: str, line: int | None = 0) -> list[str]:
    """The column's cell texts (their first line by default: a model cell holds provenance below)."""
    index = table["head"].index(name)
    return [row[index]["text"] if line is None else row[index]["text"].split("\n")[line] for row in table["rows"]]


def test_rows_appear_in_rank_order_with_shared_ranks(seen: dict[str, Any]) -> None:
    first, second = _tables(seen, "ranked")
    assert _column(first, "Rank") == ["1", "1", "3"]
    assert (
        sorted(_column(first, "Model")[:2]) == ["planner A", "planner_A"] and _column(first, "Model")[2] == "planner-B"
    )
    average = [float(v.split("\n")[0]) for v in _column(first, "Avg SR")]
    assert average == sorted(average, reverse=True) and average[0] > average[2]
    assert _column(second, "Rank") == ["1", "2"] and _column(second, "Strategy") == ["CARE", "Vanilla"]
    assert first["box"]["y"] < second["box"]["y"]  # the larger coverage first


def test_the_oracle_is_apart_and_unranked(seen: dict[str, Any]) -> None:
    ranked_models = {text for t in _tables(seen, "ranked") for text in _column(t, "Model")}
    assert "oracle" not in ranked_models
    (reference,) = [t for t in seen["tables"] if t["section"] == "reference"]
    assert "Rank" not in reference["head"] and _column(reference, "Model") == ["oracle"]
    assert reference["box"]["y"] > max(t["box"]["y"] for t in _tables(seen, "ranked"))


def test_every_row_shows_coverage_intervals_and_provenance(seen: dict[str, Any]) -> None:
    for table in _tables(seen, "board"):
        for coverage in _column(table, "Coverage", None):
            assert re.fullmatch(r"\d+/300 tasks\n16/16 conditions", coverage), coverage
        for cell in _column(table, "Avg SR", None):  # the value, and under it its interval
            assert re.fullmatch(r"\d+\.\d\n\d+–\d+", cell), cell
        planners = _column(table, "Strategy", 1)
        for planner, model in zip(planners, _column(table, "Model", None), strict=True):
            found = re.fullmatch(r"[^\n]+\nrev (\S+) · date (\S+)\ndata (\S+) · code (\S+)", model)
            assert found, model
            revision, date, dataset, code = found.groups()
            # Plans from elsewhere have no weights to hash; `talkdem score` dates its runs.
            assert revision == ("–" if planner == "external" else "r0")
            assert dataset != "–" and code != "–"
            if planner == "external":
                assert re.fullmatch(r"\d{4}-\d\d-\d\d", date), date
        assert {f"{code} {m}" for code in ("RI", "OS", "ES", "TD", "IN") for m in ("SR", "ret.")} <= set(table["head"])


def test_no_empty_cell_and_numbers_right_aligned(seen: dict[str, Any]) -> None:
    for table in _tables(seen, "board"):
        for row in table["rows"]:
            for cell in row:
                assert cell["text"], f"empty cell in {table['id']}"
                if "num" in cell["cls"].split():
                    assert cell["align"] == "right", cell  # "–" included
    cells = [c for t in _tables(seen, "board") for r in t["rows"] for c in r]
    undefined = [c for c in cells if c["text"] == "–" and "num" in c["cls"].split()]
    assert len(undefined) >= 6 and all(c["align"] == "right" for c in undefined)  # retention of the 0-SR run


def test_whole_rows_fit_the_page(seen: dict[str, Any]) -> None:
    for table in _tables(seen, "board"):
        assert table["box"]["x"] + table["box"]["w"] <= seen["viewport"], f"{table['id']} needs scrolling"


def test_nothing_overlaps_or_overflows(seen: dict[str, Any]) -> None:
    assert seen["width"] <= seen["viewport"], "the page scrolls sideways (wide tables scroll in their own box)"
    for table in seen["tables"]:
        for row in table["rows"]:
            for cell in row:
                assert cell["scrollW"] <= cell["clientW"] + 1, f"clipped text: {cell['text']!r}"
                assert cell["w"] > 0 and cell["h"] > 0
            for a, b in itertools.pairwise(row):
                assert not overlaps(a, b), (a["text"], b["text"])
    blocks = [b for b in seen["blocks"] if b["h"] > 0]
    for i, a in enumerate(blocks):
        for b in blocks[i + 1 :]:
            nested = a["x"] <= b["x"] and a["y"] <= b["y"] and a["x"] + a["w"] >= b["x"] + b["w"]
            assert nested or not overlaps(a, b), (a["tag"], a["id"], b["tag"], b["id"])


def test_screenshot_is_drawn(board: Path, tmp_path: Path) -> None:
    png = screenshot(board / "index.html", tmp_path / "board.png", tmp_path)
    assert distinct_colors(png) > 20
