"""report.html as Chromium lays it out: every figure decoded and shown, tables filled, nothing overlapping."""

from __future__ import annotations

import itertools
from pathlib import Path
from typing import Any

import pytest
from browser_helpers import distinct_colors, measure, overlaps, screenshot


@pytest.fixture(scope="module")
def seen(report: Path, tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    return measure(report / "report.html", tmp_path_factory.mktemp("chromium"))


def test_every_figure_is_loaded_and_shown(seen: dict[str, Any], report: Path) -> None:
    images = seen["images"]
    assert len(images) == len(list((report / "plots").glob("*.png")))
    for image in images:
        assert image["complete"] and image["naturalW"] > 300 and image["naturalH"] > 150, image["alt"]
        assert 0 < image["w"] <= seen["width"] and image["h"] > 0, image["alt"]  # scaled into the page
    for a, b in itertools.combinations(images, 2):
        assert not overlaps(a, b), (a["alt"], b["alt"])
    for image in images:
        for table in seen["tables"]:
            assert not overlaps(image, table["box"]), (image["alt"], table["id"])


def test_tables_are_filled_and_numbers_right_aligned(seen: dict[str, Any]) -> None:
    ids = {t["id"] for t in seen["tables"]}
    assert {"runs", "table-success", "table-retention", "table-hazards", "table-errors"} <= ids
    for table in seen["tables"]:
        for row in table["rows"]:
            for cell in row:
                assert cell["text"], f"empty cell in {table['id']}"
                assert cell["scrollW"] <= cell["clientW"] + 1, f"clipped: {cell['text']!r}"
                if "num" in cell["cls"].split():
                    assert cell["align"] == "right"
            for a, b in itertools.pairwise(row):
                assert not overlaps(a, b), (a["text"], b["text"])
    runs = next(t for t in seen["tables"] if t["id"] == "runs")
    coverage = [row[runs["head"].index("Coverage")]["text"] for row in runs["rows"]]
    assert sorted(set(coverage)) == ["1/300 tasks × 16/16 conditions", "4/300 tasks × 16/16 conditions"]
    success = next(t for t in seen["tables"] if t["id"] == "table-success")
    labels = [row[0]["text"] for row in success["rows"]]
    ours = [label for label in labels if not label.endswith("(paper)")]
    assert ours[-1] == "oracle" and labels[len(ours) :] and labels[: len(ours)] == ours, "the paper's rows follow ours"


def test_blocks_do_not_overlap(seen: dict[str, Any]) -> None:
    assert seen["width"] <= seen["viewport"], "the page scrolls sideways (wide tables scroll in their own box)"
    blocks = [b for b in seen["blocks"] if b["h"] > 0 and b["w"] > 0]
    for a, b in itertools.combinations(blocks, 2):
        nested = a["x"] <= b["x"] and a["y"] <= b["y"] and a["x"] + a["w"] >= b["x"] + b["w"]
        assert nested or not overlaps(a, b), (a["tag"], b["tag"])


def test_screenshot_is_drawn(report: Path, tmp_path: Path) -> None:
    png = screenshot(report / "report.html", tmp_path / "report.png", tmp_path, size="1400,3000")
    assert distinct_colors(png) > 50  # tables and plots, not a blank page
