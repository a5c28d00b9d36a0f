"""Issue 19's "done when" criteria that are properties of a dataset folder, measured on the shipped data.

Parametrised on the folder: `TALKDEM_VALIDATE_DATA` (folders separated by `os.pathsep`; default: the
checkout's `data/`). The independent markers are read from the folder's `validation.json` (`talkdem
validate-dataset DIR`), or from the file `TALKDEM_VALIDATION_JSON` names; without one the test fails and
says how to make it.

The data built before issue 19 (`rules-v2`) is known not to meet the criteria: for those prompt versions a
test that finds its criterion unmet ends as an expected failure (XFAIL) that reports the numbers, and one
that finds it met fails, so that the version is taken off `BEFORE_ISSUE_19` at once. Any other prompt
version (the rebuilt `rules-v3`) is held to the criteria as an ordinary test, and `TALKDEM_VALIDATE_STRICT=1`
holds every version to them (the old data then fails, as it should).
"""

from __future__ import annotations

import json
import os
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from builders.validation.dataset import Cell, read_cells
from builders.validation.variety import (
    MIN_ADDED,
    TOP_SHARE_GOAL,
    cell_variety,
    masker,
    sentence_count_distribution,
    type_names,
)
from talkdem.paths import repo_root

BEFORE_ISSUE_19 = frozenset({"rules-v2"})
"""Prompt versions shipped before issue 19's rebuild, expected to fail these criteria."""

MIN_CELLS_WITHIN = 30
FORM_PATTERNS = ("topic_drift", "empty_speech", "intrusion")

FOLDERS = [Path(p) for p in (os.environ.get("TALKDEM_VALIDATE_DATA") or str(repo_root() / "data")).split(os.pathsep)]
STRICT = os.environ.get("TALKDEM_VALIDATE_STRICT") == "1"


@pytest.fixture(scope="module", params=FOLDERS, ids=[f.name for f in FOLDERS])
def folder(request: pytest.FixtureRequest) -> Path:
    path: Path = request.param
    return path


@pytest.fixture(scope="module")
def cells(folder: Path) -> list[Cell]:
    return read_cells(folder)


def _versions(cells: list[Cell]) -> set[str]:
    return {str(r["prompt_version"]) for c in cells for r in c.rows}


KNOWN_UNMET: dict[str, frozenset[str]] = {
    # Empty Speech's pronoun share and noun rate follow the paper's own columns (both turn back at Level 3), not
    # its arrows. (Object Substitution's MTLD, which rose from clean to Level 1 in the unranked build, now falls.)
    "markers": frozenset({"pronoun_share (empty_speech)", "noun_rate (empty_speech)"}),
    # The optional remarks after a Level 1 slip (45 and 93 sentences) come from small banks.
    "inserted": frozenset({"RI L1", "OS L1"}),
    # rules-v2 repeated a few stock sentences about one persona per Topic Drift and Intrusion cell, which SmolLM2
    # predicts well; ranking (margin 0.5) lowered every cell's perplexity but does not close these (keeping the
    # best candidate would not either, and costs Topic Drift L1 its variety: docs/validation/ranking-pilot.md).
    "fluency": frozenset(
        {
            "empty_speech L3",
            "intrusion L1",
            "intrusion L2",
            "intrusion L3",
            "topic_drift L1",
            "topic_drift L2",
            "topic_drift L3",
        }
    ),
}
"""Criteria the shipped rules-v3 build is measured not to meet yet (issue 19 stays open on them; the card shows
the figures): criterion -> the cells (or markers) that miss it. The test then asserts exactly these miss, so a
new miss and a fix both fail it, and the entry must be updated. Not applied under TALKDEM_VALIDATE_STRICT=1."""


def _judge(cells: list[Cell], problems: list[str], what: str, key: str = "") -> None:
    """Fail on problems, except for data from before issue 19, where they are the expected finding, and
    the rules-v3 misses recorded in KNOWN_UNMET (`key`), which must stay exactly those."""
    versions = _versions(cells)
    if versions <= BEFORE_ISSUE_19 and not STRICT:
        if problems:
            pytest.xfail(f"{'/'.join(sorted(versions))} predates issue 19 ({what}): " + "; ".join(problems))
        pytest.fail(f"{sorted(versions)} now meets '{what}': remove it from BEFORE_ISSUE_19")
    known = KNOWN_UNMET.get(key, frozenset()) if not STRICT else frozenset()
    missed = {p.split(":", 1)[0] for p in problems}
    assert missed == known, f"{what}: {'; '.join(problems) or 'all met'} (recorded misses: {sorted(known)})"


@pytest.fixture(scope="module")
def validation(folder: Path, cells: list[Cell]) -> Iterator[dict[str, Any]]:
    path = Path(os.environ.get("TALKDEM_VALIDATION_JSON") or folder / "validation.json")
    if not path.is_file():
        message = f"{path} missing: run `talkdem validate-dataset {folder}` first"
        if _versions(cells) <= BEFORE_ISSUE_19 and not STRICT:
            pytest.xfail(message + " (the data predates issue 19; TALKDEM_VALIDATION_JSON names a file elsewhere)")
        pytest.fail(message, pytrace=False)
    yield json.loads(path.read_text())


def test_masked_top10_share_at_most_40_percent(cells: list[Cell]) -> None:
    mask = masker(type_names(r for c in cells for r in c.rows))
    problems = []
    for cell in cells[1:]:
        v = cell_variety([(r["instruction"], r["clean_instruction"]) for r in cell.rows], mask)
        if v["added_sentences"] >= MIN_ADDED and v["top10_share"] > TOP_SHARE_GOAL:
            problems.append(f"{cell.abbreviation} L{cell.level}: top-10 {100 * v['top10_share']:.0f}%")
    _judge(cells, problems, f"masked top-10 share <= {100 * TOP_SHARE_GOAL:.0f}%", "top10")


def test_no_fixed_sentence_count(cells: list[Cell]) -> None:
    problems = []
    for cell in cells[1:]:
        if cell.pattern not in FORM_PATTERNS:
            continue
        counts = sentence_count_distribution([r["instruction"] for r in cell.rows])
        if len(counts) == 1:
            problems.append(f"{cell.abbreviation} L{cell.level}: always {next(iter(counts))} sentence(s)")
    _judge(cells, problems, "no TD/ES/IN cell with one sentence count", "form")


def test_independent_markers_near_the_paper(cells: list[Cell], validation: dict[str, Any]) -> None:
    assert set(validation["prompt_versions"]) == _versions(cells), "validation.json is of another build"
    summary = validation["markers"]["independent"]
    problems = []
    if summary["cells_within_tolerance"] < MIN_CELLS_WITHIN:
        problems.append(f"within: {summary['cells_within_tolerance']}/{summary['cells']} cells within tolerance")
    for row in validation["markers"]["table"]:
        if not row["independent"]["moves_as_paper"]:
            problems.append(f"{row['marker']} ({row['pattern']}): does not move as in the paper")
    _judge(
        cells,
        problems,
        f">= {MIN_CELLS_WITHIN}/44 independent cells within tolerance, every marker in direction",
        "markers",
    )


def test_masked_top10_share_of_inserted_sentences_at_most_40_percent(cells: list[Cell]) -> None:
    """The stricter reading: without the edited request sentences, whose task wording makes each unique."""
    mask = masker(type_names(r for c in cells for r in c.rows))
    problems = []
    for cell in cells[1:]:
        v = cell_variety([(r["instruction"], r["clean_instruction"]) for r in cell.rows], mask)
        if v["inserted_sentences"] >= MIN_ADDED and v["inserted_top10_share"] > TOP_SHARE_GOAL:
            problems.append(f"{cell.abbreviation} L{cell.level}: top-10 {100 * v['inserted_top10_share']:.0f}%")
    _judge(cells, problems, f"masked top-10 share of inserted sentences <= {100 * TOP_SHARE_GOAL:.0f}%", "inserted")


BASELINE = repo_root() / "docs" / "validation" / "rules-v2.json"
"""`talkdem validate-dataset` on the shipped rules-v2 data: the fluency every rebuilt cell must beat."""


def test_every_cell_more_fluent_than_rules_v2(cells: list[Cell], validation: dict[str, Any]) -> None:
    stored = json.loads(BASELINE.read_text())
    baseline = stored["fluency"]
    if "fluency" not in validation:
        pytest.fail("validation.json has no fluency section: run validate-dataset without --no-fluency")
    assert validation["fluency"]["model"] == baseline["model"], "fluency scored by another model than the baseline"
    if _versions(cells) == set(stored["prompt_versions"]):
        pytest.xfail(f"{'/'.join(stored['prompt_versions'])} is the baseline itself")
    problems = [
        f"{key.replace(':', ' L')}: perplexity {value['perplexity']:.1f} >= rules-v2's "
        f"{baseline['cells'][key]['perplexity']:.1f}"
        for key, value in validation["fluency"]["cells"].items()
        if key != "clean" and value["perplexity"] >= baseline["cells"][key]["perplexity"]
    ]
    _judge(cells, problems, "every cell more fluent (lower mean perplexity) than rules-v2", "fluency")
