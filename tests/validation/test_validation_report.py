"""The comparison with the paper's table and its rendering, on synthetic marker means."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from builders.validation.card import validation_markdown
from builders.validation.paper import LEVEL_KEYS, PAPER
from builders.validation.report import compare_markers


def _means(scale: float) -> dict[str, dict[str, float]]:
    """Means equal to the paper's values times `scale`, keyed as the report keys cells."""
    means: dict[str, dict[str, float]] = {}
    for (marker, pattern), values in PAPER.items():
        for level, value in zip(LEVEL_KEYS, values, strict=True):
            key = "clean" if level == "clean" else f"{pattern}:{level}"
            means.setdefault(key, {})[marker] = value * scale
    return means


def test_the_papers_own_numbers_are_within_but_not_all_monotonic() -> None:
    rows = compare_markers(_means(1.0), None)
    assert all(all(r["independent"]["within_tolerance"].values()) for r in rows)
    assert all(r["ours"] is None for r in rows)
    not_monotonic = {(r["marker"], r["pattern"]) for r in rows if not r["independent"]["moves_as_paper"]}
    # the paper's own columns: OS repairs dip at L2, RI pronouns dip at L1, ES pronouns and nouns turn at L3
    assert not_monotonic == {
        ("repair_rate", "object_substitution"),
        ("pronoun_share", "referential_imprecision"),
        ("pronoun_share", "empty_speech"),
        ("noun_rate", "empty_speech"),
    }


def test_far_values_are_flagged_and_rendered() -> None:
    rows = compare_markers(_means(2.0), _means(1.1))
    far = next(r for r in rows if r["marker"] == "mtld")
    assert far["independent"]["within_tolerance"] == {k: False for k in LEVEL_KEYS}
    assert all(far["ours"]["within_tolerance"].values())
    report: dict[str, Any] = {
        "prompt_versions": ["rules-test"],
        "markers": {
            "table": rows,
            "independent": {"cells_within_tolerance": 2, "cells": 44, "markers_moving_as_paper": 7, "markers": 11},
            "ours": None,
        },
        "variety": {
            "clean": {"sentence_counts": {"1": 3}},
            "object_substitution:2": {
                "added_sentences": 40,
                "templates": 2,
                "top10_share": 1.0,
                "top10": [{"sentence": "The <obj> | I meant", "count": 39}],
                "inserted_sentences": 20,
                "inserted_templates": 1,
                "inserted_top10_share": 1.0,
                "four_grams": 10,
                "distinct_four_grams": 5,
                "distinct_four_gram_share": 0.5,
                "sentence_counts": {"2": 3},
            },
        },
    }
    text = validation_markdown(report)
    assert "**2 of 44 cells**" in text and "Lexical diversity (MTLD) (OS): outside the paper's band" in text
    assert "| OS | 2 | 40 | 2 | 100% ✗ | 20 | 1 | 100% |" in text  # 20 inserted: under the 30 of the goal
    assert r"The &lt;obj&gt; \| I meant (39)" in text  # the embedded sentence cannot break the table
    assert "Ours (`builders/markers`): not computed" in text


def test_the_card_judges_the_papers_own_column_by_the_same_rule() -> None:
    # the paper's own numbers as the independent column: step by step where the paper is, clean to L3 everywhere
    rows = compare_markers(_means(1.0), None)
    summary = {"cells_within_tolerance": 44, "cells": 44, "markers_moving_as_paper": 7, "markers": 11}
    report: dict[str, Any] = {
        "prompt_versions": ["rules-test"],
        "markers": {"table": rows, "independent": summary, "ours": None},
        "variety": {"clean": {"sentence_counts": {"1": 3}}},
    }
    text = validation_markdown(report)
    assert "11 of 11 markers move from clean to L3 in the paper's direction, 7 of 11 step by step" in text
    assert "The paper's own table moves step by step in its direction for 7 of 11 markers" in text
    assert "Pronoun share (RI) at L1" in text and "Repair / self-correction rate (per 100 words) (OS) at L2" in text
    assert "Pronoun share (ES): does not move step by step in the paper's direction (neither does the paper's" in text
    mtld = next(line for line in text.splitlines() if line.startswith("| Lexical diversity (MTLD) | OS |"))
    assert mtld.endswith("| yes / - / yes | - / yes |")
    repair = next(line for line in text.splitlines() if line.startswith("| Repair / self-correction rate"))
    assert repair.endswith("| no / - / NO | - / yes |")  # capitals flag a column of ours


def test_command_refuses_a_folder_that_is_not_a_dataset(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from talkdem.cli import main

    (tmp_path / "clean").mkdir()
    assert main(["validate-dataset", str(tmp_path), "--no-fluency"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "clean/test.parquet: not a TALK-Dem dataset folder" in err[0]
    assert main(["validate-dataset", str(tmp_path / "missing")]) == 2
    assert "no such dataset folder" in capsys.readouterr().err
