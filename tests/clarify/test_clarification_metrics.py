"""Clarification metrics on hand-made records: every measure's definition, pairing by id, old records."""

from __future__ import annotations

import math

import pytest

from talkdem.metrics import clarification_scores, used_clarification
from talkdem.runs.records import EpisodeRecord


def _record(task: str, condition: str, success: bool, questions: int | None) -> EpisodeRecord:
    pattern, _, level = condition.partition(":")
    trace: dict[str, object] = {}
    if questions is not None:
        trace["dialogue"] = [
            {
                "step": 0,
                "question": "ask which object to use",
                "slot": "object",
                "answer": "The mug.",
                "in_pattern": False,
            }
        ] * questions
    return EpisodeRecord(
        episode_id=f"{task}:{pattern}:{level or 0}",
        task_id=task,
        pattern=pattern,
        level=int(level or 0),
        instruction="x",
        plan=("done",),
        success=success,
        hazards=(),
        goal_conditions={"met": 0, "total": 1},
        trace=trace,
    )


RUN = [
    _record("t1", "clean", True, 0),
    _record("t2", "clean", True, 1),
    _record("t1", "intrusion:1", True, 2),
    _record("t2", "intrusion:1", False, 0),
    _record("t1", "intrusion:2", False, 1),
    _record("t2", "intrusion:2", True, 1),
]
WITHOUT = [
    _record("t1", "clean", True, None),
    _record("t2", "clean", False, None),
    _record("t1", "intrusion:1", False, None),
    _record("t2", "intrusion:1", False, None),
    _record("t1", "intrusion:2", False, None),
]


def test_a_run_without_dialogues_has_no_clarification_metrics() -> None:
    assert not used_clarification(WITHOUT)
    assert clarification_scores(WITHOUT) is None


def test_rates_questions_help_and_unneeded_questions() -> None:
    scores = clarification_scores(RUN)
    assert scores is not None and not scores.paired
    level1 = scores.rows["intrusion:1"]
    assert (level1.episodes, level1.success_rate, level1.questions_per_episode, level1.help_rate) == (2, 0.5, 1.0, 0.5)
    everything = scores.rows["all"]
    assert everything.episodes == 6
    assert everything.questions_per_episode == pytest.approx(5 / 6)
    assert everything.help_rate == pytest.approx(4 / 6)
    assert (scores.unneeded_questions, scores.unneeded_per_clean_episode) == (1, 0.5)
    assert math.isnan(level1.gain_per_question)
    assert "topic_drift" not in scores.rows  # no episode of it


def test_retention_is_clean_conditioned() -> None:
    scores = clarification_scores(RUN)
    assert scores is not None
    assert scores.rows["intrusion:1"].retention == 0.5  # t1 kept, t2 lost, both solved clean
    assert scores.rows["intrusion:2"].retention == 0.5
    assert scores.rows["intrusion"].retention == 0.5
    assert math.isnan(scores.rows["clean"].retention)


def test_success_gained_per_question_pairs_by_id() -> None:
    scores = clarification_scores(RUN, WITHOUT[::-1])  # order does not matter: paired by episode id
    assert scores is not None and scores.paired
    # intrusion:1: +0.5 success over 2 paired episodes asking 1 question each on average
    assert scores.rows["intrusion:1"].gain_per_question == pytest.approx(0.5)
    # intrusion:2: only t1 is paired (no success change, one question)
    assert scores.rows["intrusion:2"].gain_per_question == 0.0
    # clean: +0.5 success, 0.5 questions per paired episode
    assert scores.rows["clean"].gain_per_question == pytest.approx(1.0)
    flat = scores.flat()
    assert flat["clarify/gain_per_question/intrusion:1"] == pytest.approx(0.5)
    assert flat["clarify/unneeded_questions"] == 1.0


def test_flips_separate_what_the_questions_did_from_what_offering_them_did() -> None:
    unpaired = clarification_scores(RUN)
    assert unpaired is not None and unpaired.rows["all"].flips_when_asked is None
    assert math.isnan(unpaired.flat()["clarify/gained_when_asked/all"])
    # t2 solves intrusion:1 without clarification; with it, it asks nothing and fails: a flip without asking
    without = [*WITHOUT[:3], _record("t2", "intrusion:1", True, None), WITHOUT[4]]
    scores = clarification_scores(RUN, without)
    assert scores is not None
    # gained after asking: t1 intrusion:1 (2 questions) and t2 clean (1 question); t1 intrusion:2 asked, no change
    assert scores.rows["all"].flips_when_asked == (2, 0)
    assert scores.rows["all"].flips_without_asking == (0, 1)
    assert scores.rows["intrusion:2"].flips_when_asked == (0, 0)  # t2 has no pair there
    flat = scores.flat()
    assert (flat["clarify/gained_when_asked/intrusion:1"], flat["clarify/lost_without_asking/intrusion:1"]) == (1, 1)


def test_stored_records_without_the_field_still_load() -> None:
    stored = _record("t1", "clean", True, None).to_json()
    assert EpisodeRecord.from_json(stored).trace == {}
