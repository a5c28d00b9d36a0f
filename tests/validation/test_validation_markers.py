"""The independent markers on hand-written sentences, with the expected values counted by hand."""

from __future__ import annotations

import math
import shutil
from pathlib import Path
from typing import Any

import pytest

from builders.validation.markers import discourse_marker_count, doc_markers, mtld, parse_depth, repair_count
from builders.validation.pipeline import PipelineIntegrityError, load_pipeline, verify_pipeline


@pytest.fixture(scope="module")
def nlp() -> Any:
    return load_pipeline()


def test_mtld_by_hand() -> None:
    # "a b a b": the third word drops the TTR to 2/3 <= 0.72 (one factor); "b" is left with TTR 1 (partial 0)
    assert mtld(["a", "b", "a", "b"]) == 4.0
    # "a b c a": TTR ends at 3/4, a partial factor of 0.25 / 0.28 each way
    assert math.isclose(mtld(["a", "b", "c", "a"]), 4 / (0.25 / 0.28))
    assert mtld(["a", "b", "c"]) == 3.0  # all distinct: one factor
    assert mtld([]) == 0.0
    assert mtld(["The", "the"]) == mtld(["the", "the"])  # lowercased


def test_discourse_markers_by_hand(nlp: Any) -> None:
    # well, um, you know, uh (the phrase once); not "please", not the coordinating "and" inside the clause
    assert discourse_marker_count(nlp("Well, um, could you, you know, please put the mug, uh, in the sink?")) == 4
    # left periphery: "And", "then", "well" open the sentence; the "and" and "as well" later are ordinary words
    assert discourse_marker_count(nlp("And then, well, put it in and close it as well.")) == 3
    assert discourse_marker_count(nlp("Hello, please put the apple in the fridge, thanks.")) == 0


def test_repairs_by_hand(nlp: Any) -> None:
    assert repair_count(nlp("Put the apple in the fridge.")) == 0
    assert repair_count(nlp("There is no milk in the fridge.")) == 0  # "no" the determiner
    # "no" and "sorry" are two words apart: one repair, whose alteration is "the blue box"
    assert repair_count(nlp("Put it in the red box, no, sorry, the blue box.")) == 1
    # no editing term: a second direct object of "put" is the alteration of the first
    assert repair_count(nlp("Put the mug, uh, the cup in the sink.")) == 1
    assert repair_count(nlp("It is rather big, put it in the box.")) == 0  # the degree adverb
    # two corrections far apart in two sentences
    assert repair_count(nlp("Get the spoon, I mean the fork. Put it in the drawer, or rather the sink.")) == 2


def test_ratios_by_hand(nlp: Any) -> None:
    values = doc_markers(nlp("Could you grab the thing and put it on the table?"))
    # words: could you grab the thing and put it on the table (11); pronouns: you, it; nouns: thing, table;
    # "thing" is one of Halliday & Hasan's general nouns
    assert values["pronoun_share"] == 2 / 4
    assert values["vague_reference_share"] == 3 / 4
    assert values["noun_rate"] == 2 / 11
    assert values["specific_noun_rate"] == 1 / 11
    assert values["discourse_markers"] == 0 and values["repair_rate"] == 0


def test_parse_depth_by_hand(nlp: Any) -> None:
    # put -> in -> fridge -> the: three arcs; the second sentence "Thanks." is its own root (depth 0)
    assert parse_depth(nlp("Put the apple in the fridge.")) == 3
    assert parse_depth(nlp("Put the apple in the fridge. Thanks.")) == 1.5


def test_pipeline_is_verified_and_a_changed_file_is_refused(tmp_path: Path) -> None:
    check = verify_pipeline()
    assert check.official_files >= 6 and check.observed_files >= 10
    copy = tmp_path / "model"
    shutil.copytree(check.model_dir, copy)
    assert verify_pipeline(copy).model_dir == copy
    with (copy / "tagger" / "model").open("ab") as handle:
        handle.write(b"\0")
    with pytest.raises(PipelineIntegrityError, match="tagger/model differs"):
        verify_pipeline(copy)
    (copy / "parser" / "model").unlink()
    with pytest.raises(PipelineIntegrityError, match="parser/model missing"):
        verify_pipeline(copy)
