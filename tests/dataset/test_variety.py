"""Variety figures: added sentences, repeated openers, article agreement; the shipped data meets the goal
(except where `KNOWN_MISSES` records it does not)."""

from __future__ import annotations

import json

import talk_dem
from builders.markers.variety import (
    TOP5_GOAL,
    added_sentences,
    article_errors,
    cell_variety,
    repeated_opener,
)
from talkdem.paths import repo_root
from talkdem.speech.cues import openers

DATA = repo_root() / "data"

KNOWN_MISSES = {("referential_imprecision", "1")}
"""Cells of the shipped data whose five most frequent added sentences reach the 10% goal. Referential
Imprecision L1: ranking (issue 19) favours the stock remarks after the slip, from a bank of 45 ("I knew it all
along, really." 11 times in 389 added sentences; top five 10.3%, unranked 9.4%). Must match exactly: a new miss
and a fix both fail the test, and the entry is updated with the figures."""


def test_openers_are_short_lead_ins() -> None:
    text = "Mind you, the lamp is old. Where was I? Oh yes, on the table. The cat, fed, out all night long."
    assert openers(text) == ["mind you", "oh yes", "the cat"]
    assert repeated_opener("Oh, hello there. Oh, the lamp.")
    assert not repeated_opener("Oh, hello there. Anyway, the lamp. I was saying, as it happens, that.")


def test_added_sentences_are_those_the_clean_control_lacks() -> None:
    clean = "Hi, put the apple on the table."
    variant = "Hi, put the apple on the table. Oh, the lamp. Oh, the lamp."
    assert added_sentences(variant, clean) == ["Oh, the lamp.", "Oh, the lamp."]
    figures = cell_variety([(variant, clean), (clean + " Well, one of those days.", clean)])
    assert figures["added_sentences"] == 3 and figures["distinct_added_sentences"] == 2
    assert abs(figures["top5_share"] - 1.0) < 1e-12
    assert figures["repeated_opener_utterances"] == 1


def test_article_errors_count_only_new_disagreements() -> None:
    seed_error = "Please put a apple on the table."
    assert article_errors("Place a cooled bread there.", "Place a cooled apple there.") == 1
    assert article_errors("Place some cooled bread there.", "Place a cooled apple there.") == 0
    assert article_errors("Put an mug and a box with keys and a loaf of bread.", "") == 1
    assert article_errors(seed_error + " Yes, put a apple.", seed_error) == 0  # the seed's own typo
    assert article_errors("a toilet paper holder, an egg, a one, an hour", "") == 0


def test_shipped_data_meets_the_variety_goal() -> None:
    from builders.markers.report import compute_variety

    variety = compute_variety(DATA)
    misses = [
        (pattern, level, v["repeated_opener_utterances"], v["article_errors"])
        for pattern, levels in variety.items()
        for level, v in levels.items()
        if v["repeated_opener_utterances"] or v["article_errors"]
    ]
    assert not misses
    top5 = {(p, lvl): round(v["top5_share"], 3) for p, levels in variety.items() for lvl, v in levels.items()}
    assert {cell for cell, share in top5.items() if share >= TOP5_GOAL} == KNOWN_MISSES, top5
    assert set(variety) == set(talk_dem.PATTERNS)
    # the figures in markers.json (and the card) are those of the shipped data
    assert json.loads((DATA / "markers.json").read_text())["variety"] == json.loads(json.dumps(variety))
