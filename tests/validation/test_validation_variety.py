"""Masked variety and sentence counts on a tiny synthetic cell; the card's rendering of them."""

from __future__ import annotations

from builders.validation.card import escape_markdown
from builders.validation.variety import (
    added_sentences,
    cell_variety,
    masker,
    object_forms,
    sentence_count_distribution,
    type_names,
)


def test_object_forms_from_type_names() -> None:
    assert {"baseball bat", "baseballbat", "baseball bats", "bat"} - object_forms("BaseballBat") == {"bat"}
    assert {"desk lamp", "desklamp", "lamp", "lamps"} <= object_forms("DeskLamp")
    assert "can" not in object_forms("GarbageCan")  # a three-letter head is mostly the verb
    assert {"tv stand", "stand"} <= object_forms("TVStand")
    assert {"box", "boxes"} <= object_forms("Box")


def test_type_names_come_from_the_rows() -> None:
    rows = [
        {"scene_objects": ["Mug", "Sink"], "pddl_params": {"object_target": "Mug", "parent_target": None}},
        {"scene_objects": ["Apple"], "pddl_params": {"object_target": "Apple", "toggle_target": "DeskLamp"}},
    ]
    assert type_names(rows) == {"Mug", "Sink", "Apple", "DeskLamp"}


def test_masked_variety_counts_templates_not_objects() -> None:
    mask = masker(["Mug", "Cup", "Box", "DeskLamp", "KeyChain"])
    clean = ["Put the mug in the sink.", "Put the cup in the box.", "Look at the box under the desk lamp."]
    pairs = [
        (clean[0] + " The mug, I meant the mug.", clean[0]),
        (clean[1] + " The cup, I meant the cup.", clean[1]),
        (clean[2] + " The box, I meant the box. Funny, the key chains.", clean[2]),
    ]
    result = cell_variety(pairs, mask)
    assert result["added_sentences"] == 4
    assert result["templates"] == 2  # "The <obj>, I meant the <obj>." three times, "Funny, the <obj>." once
    assert result["top10"][0] == {"sentence": "The <obj>, I meant the <obj>.", "count": 3}
    assert result["top10_share"] == 1.0
    assert result["sentence_counts"] == {2: 2, 3: 1}
    # none of the four is an edited clean sentence
    assert result["inserted_sentences"] == 4 and result["inserted_templates"] == 2
    # 4-grams of the masked sentences: "the <obj> i meant", "<obj> i meant the", "i meant the <obj>" (x3 each)
    assert result["distinct_four_grams"] == 3 and result["four_grams"] == 9


def test_edited_request_sentences_are_not_inserted_ones() -> None:
    mask = masker(["Mug", "Sink", "Apple"])
    clean = "Hello, put the mug in the sink, thanks."
    pairs = [
        ("Hello, put the thingy in the sink, thanks. I mean the mug.", clean),
        ("Hello, put the, oh, the dog, the mug in the sink, thanks.", clean),
    ]
    result = cell_variety(pairs, mask)
    assert result["added_sentences"] == 3
    assert result["inserted_sentences"] == 1  # "I mean the <obj>."; the other two are the request edited
    assert result["inserted_top10_share"] == 1.0


def test_added_sentences_are_a_multiset_difference() -> None:
    assert added_sentences("Hi. Put it there. Hi.", "Hi. Put it there.") == ["Hi."]
    assert added_sentences("Put it there.", "Put it there.") == []
    assert sentence_count_distribution(["One. Two.", "One!", "One? Two. Three."]) == {1: 1, 2: 1, 3: 1}


def test_markdown_escape_keeps_tables_and_html_intact() -> None:
    assert escape_markdown("The <obj> | a_b *c*\nnext") == r"The &lt;obj&gt; \| a\_b \*c\* next"
