"""Linguistic markers: the measures, the statistics, the optional CHAT comparison, and the shipped results."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import pytest

from builders.markers.measures import discourse_markers, load_pipeline, mtld, text_markers
from builders.markers.stats import cohens_d, delta_w_l3, mann_whitney
from talkdem.paths import repo_root

DATA = repo_root() / "data"


def test_mtld_drops_with_repetition() -> None:
    varied = "put the red apple on the small wooden table near my old blue chair today please".split()  # noqa: SIM905
    repeated = "put the the apple apple on the the table table the the apple apple on the table".split()  # noqa: SIM905
    assert mtld(varied) > mtld(repeated)
    assert mtld([]) == 0.0


def test_discourse_markers_need_a_clause_boundary() -> None:
    assert discourse_markers("Well, you know, put it there. So, anyway, thanks.") == 4
    assert discourse_markers("Thank you so much, I'd like you to see it well.") == 0


def test_text_markers_on_a_parse() -> None:
    nlp = load_pipeline()
    plain = text_markers(nlp("Could you put the apple on the table?"))
    vague = text_markers(nlp("Could you put the thing, you know, that one, no, sorry, it on there?"))
    assert plain["repair_rate"] == 0 and vague["repair_rate"] > 0
    assert vague["vague_reference_share"] > plain["vague_reference_share"]
    assert vague["specific_noun_rate"] < plain["specific_noun_rate"]
    assert plain["parse_depth"] >= 2


def test_cohens_d_and_tests() -> None:
    dementia, control = [3.0, 4.0, 5.0, 6.0], [1.0, 2.0, 3.0, 4.0]
    assert math.isclose(cohens_d(dementia, control), 2 / math.sqrt(5 / 3))
    u, p = mann_whitney(dementia, control)
    assert 0 <= p <= 1 and u > 8
    assert delta_w_l3([5.0, 6.0], control, dementia) > 0  # level 3 sits with the dementia group


CHAT_DEMENTIA = """@Begin
@Participants:\tPAR Participant, INV Investigator
*INV:\ttell me what you see .
*PAR:\tthe &uh boy is [//] the boy is taking the thing up there &um cookie .
*PAR:\tand the &uh the mother she is [//] she's doing the dishes and it's [/] it's spilling over .
*PAR:\tthe girl she wants one too you know and the stool is +/.
*PAR:\twell the water is on the floor there and that's about it I think yeah .
@End
"""
CHAT_CONTROL = """@Begin
@Participants:\tPAR Participant, INV Investigator
*PAR:\tthe boy is standing on a stool reaching into the cookie jar on the top shelf .
*PAR:\this sister is reaching up for a cookie while the stool tips over beneath him .
*PAR:\tthe mother is drying a plate at the sink and the water overflows onto the kitchen floor .
*PAR:\tthrough the window you can see the garden path and a neighbouring house .
@End
"""


def write_chat(root: Path) -> Path:
    for group, text, count in (("dementia", CHAT_DEMENTIA, 3), ("control", CHAT_CONTROL, 3)):
        folder = root / group
        folder.mkdir(parents=True)
        for i in range(count):
            (folder / f"{group}{i}.cha").write_text(text.replace("boy", "boy" if i % 2 else "lad"))
    return root


def test_chat_reading_chunks_and_counts_repairs(tmp_path: Path) -> None:
    from builders.markers.chat import chunk_transcript, read_chat_folder

    write_chat(tmp_path)
    chunks = chunk_transcript(tmp_path / "dementia" / "dementia0.cha")
    assert chunks and all(len(c.text.split()) >= 25 for c in chunks)
    assert sum(c.repairs for c in chunks) == 2  # the two [//] retracings
    assert "&uh" not in chunks[0].text and "[//]" not in chunks[0].text
    groups = read_chat_folder(tmp_path)
    assert set(groups) == {"dementia", "control"}


def test_dementiabank_comparison_on_a_synthetic_sample(tmp_path: Path) -> None:
    from builders.markers.report import compare_dementiabank

    nlp = load_pipeline()
    level3 = {
        p: [text_markers(nlp(t)) for t in ("Put the, the thing, no, that one there. You know.", "Oh. Well. It, it.")]
        for p in ("object_substitution", "referential_imprecision", "empty_speech", "intrusion", "topic_drift")
    }
    rows = compare_dementiabank(write_chat(tmp_path), level3)
    by_marker = {(r["marker"], r["pattern"]): r for r in rows}
    repair = by_marker[("repair_rate", "object_substitution")]
    assert repair["dementia_mean"] > repair["control_mean"] == 0
    assert repair["cohens_d"] > 0 and 0 <= repair["p_value"] <= 1
    assert all({"mann_whitney_u", "delta_w_l3", "significant"} <= set(r) for r in rows)
    assert ("relevance", "topic_drift") not in by_marker  # no reference text given


def test_shipped_markers_move_in_the_papers_directions() -> None:
    markers = json.loads((DATA / "markers.json").read_text())
    assert markers["pipeline"].startswith("en_core_web_sm 3.8")
    checked = {(d["marker"], d["pattern"]) for d in markers["directions"]}
    assert len(checked) == 11
    not_holding = {
        (d["marker"], d["pattern"])
        for d in markers["directions"]
        if not d["holds"] and not _moves_as_the_papers_column(d)
    }
    # Every marker either follows the paper's arrow step by step or, where the paper's own column turns back,
    # that column (Empty Speech's pronoun share and noun rate). A new departure fails here and must be recorded
    # in KNOWN_DEPARTURES with its reason.
    assert not_holding == KNOWN_DEPARTURES
    card = (DATA / "README.md").read_text()
    assert "| Repair / self-correction rate (per 100 words) | OS | up |" in card


@pytest.mark.slow
def test_shipped_markers_are_reproduced() -> None:
    from builders.markers.report import compute_cells, directions

    stored = {
        (d["marker"], d["pattern"]): d["values"] for d in json.loads((DATA / "markers.json").read_text())["directions"]
    }
    for entry in directions(compute_cells(DATA, relevance=False)):
        for key, value in entry["values"].items():
            assert math.isclose(value, stored[(entry["marker"], entry["pattern"])][key], rel_tol=1e-9)


def test_tolerance_has_a_floor_near_zero() -> None:
    from builders.markers.paper import tolerance, within

    assert within("repair_rate", 0.0, 0.4) and not within("repair_rate", 0.0, 0.6)
    assert within("discourse_markers", 8.97, 11.0) and not within("discourse_markers", 8.97, 11.5)
    assert tolerance("relevance", 0.957) == 0.25 * 0.957


def test_relevance_is_sentence_level() -> None:
    from builders.markers.measures import relevance, sentences

    assert sentences("Hi, put it there. Oh! Is it? yes.") == ["Hi, put it there.", "Oh!", "Is it?", "yes."]
    seed = "Put the apple on the table."
    on_task, drifted, far = relevance(
        [
            "Could you put the apple on the table?",
            "Could you put the apple on the table? My brother had a red bicycle.",
            "Could you put the apple on the table? My brother had a red bicycle. The summers were long then.",
        ],
        [seed] * 3,
    )
    assert on_task > 0.8 and on_task > drifted > far  # each off-task sentence takes its share


def test_shipped_markers_are_near_the_papers_table() -> None:
    """Issue 14: at least 35 of the 44 cells within tolerance of the paper's; every marker in its direction."""
    from builders.markers.paper import LEVEL_KEYS, PAPER, within

    markers = json.loads((DATA / "markers.json").read_text())
    inside = 0
    for entry in markers["directions"]:
        paper = PAPER[(entry["marker"], entry["pattern"])]
        inside += sum(within(entry["marker"], p, entry["values"][k]) for p, k in zip(paper, LEVEL_KEYS, strict=True))
    assert len(markers["directions"]) == len(PAPER) == 11
    assert inside >= 35, f"only {inside} of 44 marker cells are within tolerance of the paper's"
    assert {
        (d["marker"], d["pattern"]) for d in markers["directions"] if not (d["holds"] or _moves_as_the_papers_column(d))
    } == KNOWN_DEPARTURES
    card = (DATA / "README.md").read_text()
    assert f"**{inside} of 44 cells**" in card


KNOWN_DEPARTURES: set[tuple[str, str]] = set()
"""Markers of the shipped data that move neither as the paper's arrow nor as its column. Empty since the ranked
build (2026-12-04): the unranked rules-v3 build's Object Substitution MTLD rose from clean to Level 1."""


def _moves_as_the_papers_column(entry: dict[str, Any]) -> bool:
    from builders.markers.paper import follows_papers_column

    return follows_papers_column(entry["marker"], entry["pattern"], entry["values"])


def test_a_turning_column_may_be_followed_only_where_the_paper_turns() -> None:
    from builders.markers.paper import follows_papers_column

    # Empty Speech pronoun share: the paper goes up, up, down
    assert follows_papers_column("pronoun_share", "empty_speech", {"clean": 0.2, "1": 0.3, "2": 0.5, "3": 0.45})
    assert not follows_papers_column("pronoun_share", "empty_speech", {"clean": 0.2, "1": 0.3, "2": 0.5, "3": 0.55})
    # a marker whose paper column is monotonic has only the arrow
    assert not follows_papers_column("parse_depth", "intrusion", {"clean": 3.4, "1": 2.7, "2": 2.6, "3": 2.7})


def test_the_card_says_how_each_turning_marker_moves_on_this_data() -> None:
    card = (DATA / "README.md").read_text()
    for entry in json.loads((DATA / "markers.json").read_text())["directions"]:
        if (entry["marker"], entry["pattern"]) == ("noun_rate", "empty_speech"):
            expected = "the paper's arrow" if entry["holds"] else "the paper's own column"
            line = next(x for x in card.splitlines() if x.startswith("- Noun rate (empty speech)"))
            assert f"it follows {expected}" in line
