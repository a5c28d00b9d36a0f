"""Records read from disk are validated by one schema (`EpisodeRecord.from_json`, `talkdem.runs.record_fields`)
before any command uses them: a damaged nested field (a dialogue step that is a list, a huge float, hazards
that are strings, a step index that is text, ...) is one `RecordError` naming the file, the line, the episode
and the field, for the viewer, the report, the error sample and pack alike; never a TypeError or
OverflowError from deep inside a command."""

from __future__ import annotations

import copy
import gzip
import json
import shutil
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from talkdem.cli import main
from talkdem.runs import EpisodeRecord, read_episodes
from talkdem.runs.records import RecordError

COMMITTED = Path(__file__).resolve().parent.parent.parent / "results" / "paper" / "qwen2.5-coder-0.5b-care"


def _records() -> list[dict[str, Any]]:
    """The first committed episodes: a clean one and pattern ones of the same task, with full traces."""
    with gzip.open(COMMITTED / "episodes.jsonl.gz", "rt", encoding="utf-8") as handle:
        return [json.loads(next(handle)) for _ in range(3)]


GOOD = _records()
DIALOGUE = {"step": 1, "question": "Which book?", "slot": "object", "answer": "the red one", "in_pattern": False}


def _run(folder: Path, records: list[dict[str, Any]]) -> Path:
    folder.mkdir(parents=True)
    shutil.copy(COMMITTED / "header.json", folder / "header.json")
    # json.dumps writes a float infinity as `Infinity` and a NaN as `NaN`: what a hand-edit could leave.
    text = "".join(json.dumps(r) + "\n" for r in records)
    (folder / "episodes.jsonl").write_text(text, encoding="utf-8")
    return folder


def _set(path: str, value: Any) -> Callable[[dict[str, Any]], None]:
    """Set `path` (dotted, list indexes as numbers) of a record to `value`."""

    def change(record: dict[str, Any]) -> None:
        *parents, last = path.split(".")
        target: Any = record
        for part in parents:
            target = target[int(part)] if isinstance(target, list) else target.setdefault(part, {})
        if isinstance(target, list):
            target[int(last)] = value
        else:
            target[last] = value

    return change


def _drop(path: str) -> Callable[[dict[str, Any]], None]:
    def change(record: dict[str, Any]) -> None:
        *parents, last = path.split(".")
        target: Any = record
        for part in parents:
            target = target[int(part)] if isinstance(target, list) else target[part]
        del target[last]

    return change


BROKEN = [
    # The examples: a dialogue step that is a list, a huge float, not a list; hazards that are strings.
    (_set("trace.dialogue", [[1, "q"]]), "trace.dialogue[0]", "an object"),
    (_set("trace.dialogue", [{**DIALOGUE, "step": 1e400}]), "trace.dialogue[0].step", "whole number"),
    (_set("trace.dialogue", [{**DIALOGUE, "step": [2]}]), "trace.dialogue[0].step", "whole number"),
    (_set("trace.dialogue", [{**DIALOGUE, "step": 2.0}]), "trace.dialogue[0].step", "whole number"),
    (_set("trace.dialogue", "asked twice"), "trace.dialogue", "a list"),
    (_set("trace.dialogue", [{**DIALOGUE, "in_pattern": "no"}]), "trace.dialogue[0].in_pattern", "true or false"),
    (_set("trace.dialogue", [{k: v for k, v in DIALOGUE.items() if k != "answer"}]), "trace.dialogue[0]", "'answer'"),
    (_set("hazards", ["fire"]), "hazards[0]", "an object"),
    (_set("hazards", [{"category": "fire", "step": 0}]), "hazards[0].category", "one of"),
    (_set("hazards", [{"category": "appliance_left_running", "step": -1}]), "hazards[0].step", "whole number"),
    (_set("hazards", [{"category": "appliance_left_running", "step": 10**40}]), "hazards[0].step", "whole number"),
    # `invalid literal for int() with base 10: 'abc'`, and its neighbours in the steps.
    (_set("trace.steps.0.index", "abc"), "trace.steps[0].index", "whole number"),
    (_set("trace.steps.0.ok", "yes"), "trace.steps[0].ok", "true or false"),
    (_set("trace.steps.0.skill", None), "trace.steps[0].skill", "a string"),
    (_set("trace.steps.0.failure", "exploded"), "trace.steps[0].failure", "one of"),
    (_set("trace.steps.0", "find a book"), "trace.steps[0]", "an object"),
    (_drop("trace.steps.0.location"), "trace.steps[0]", "'location'"),
    (_set("trace.steps", {"0": {}}), "trace.steps", "a list"),
    (_set("trace.end_reason", "exploded"), "trace.end_reason", "one of"),
    (_set("trace.goal.conditions", 5), "trace.goal.conditions", "a list"),
    (_set("trace.goal.conditions", [{"name": "x", "met": 1}]), "trace.goal.conditions[0].met", "true or false"),
    (_set("trace.hazards", [{"category": "x"}]), "trace.hazards[0]", "'rule'"),
    (_set("trace.analysis.failed_steps", [[1e400, "blocked"]]), "trace.analysis.failed_steps[0][0]", "whole number"),
    (_set("trace.analysis.repeated_steps", "2"), "trace.analysis.repeated_steps", "whole number"),
    (_set("trace.analysis.placed", [["a"]]), "trace.analysis.placed[0]", "a pair"),
    (_drop("trace.analysis"), "trace", "'analysis'"),
    (_set("trace.thoughts", [1]), "trace.thoughts[0]", "a string"),
    (_set("trace.final_state", []), "trace.final_state", "an object"),
    (_set("goal_conditions", {"met": 3, "total": 2}), "goal_conditions.met", "must not exceed"),
    (_set("goal_conditions", {"met": 1.5, "total": 2}), "goal_conditions.met", "whole number"),
    (_set("goal_conditions", {"met": 1}), "goal_conditions", "'total'"),
    (_set("timing", {"planning_seconds": float("nan")}), "timing.planning_seconds", "finite number"),
    (_set("timing", {"planning_seconds": float("inf")}), "timing.planning_seconds", "finite number"),
    (_set("timing", {"planning_seconds": -1.0}), "timing.planning_seconds", "finite number"),
    (_set("timing", {"planning_seconds": 10**400}), "timing.planning_seconds", "finite number"),
    (_set("timing", {"planning_seconds": "3s"}), "timing.planning_seconds", "finite number"),
    (_set("notes", {"rewrite": 5}), "notes.rewrite", "a string"),
    (_set("notes", {"top_candidates": "[[["}), "notes.top_candidates", "JSON text"),
    (_set("notes", {"top_candidates": "[" * 100_000}), "notes.top_candidates", "JSON text"),
    (_set("notes", {"top_candidates": "[[[1, 2]]]"}), "notes.top_candidates[0][0]", "a pair"),
    (_set("notes", {"top_candidates": '[[["find a book", "high"]]]'}), "notes.top_candidates[0][0]", "a pair"),
    (_set("notes", {"top_candidates": '[[["find a book", ' + "9" * 5000 + "]]]"}), "notes.top_candidates", "JSON"),
    (_set("trace", []), "'trace' must be dict", ""),
    (_set("hazards", "fire"), "'hazards' must be list", ""),
]


@pytest.mark.parametrize(("change", "field", "expected"), BROKEN)
def test_a_broken_nested_field_names_file_line_episode_and_field(
    change: Callable[[dict[str, Any]], None], field: str, expected: str, tmp_path: Path
) -> None:
    records = copy.deepcopy(GOOD)
    change(records[1])
    run = _run(tmp_path / "run", records)
    with pytest.raises(RecordError) as error:
        read_episodes(run)
    message = str(error.value)
    assert "\n" not in message
    assert f"{run / 'episodes.jsonl'}, line 2 ({records[1]['episode_id']})" in message
    assert field in message and expected in message


def test_what_the_writers_write_passes() -> None:
    for record in GOOD:
        assert EpisodeRecord.from_json(record).to_json() == record
    scores = '[[["find a book", -0.25], ["find a desk", -Infinity]], []]'  # a masked skill scores -inf
    with_extras = copy.deepcopy(GOOD[1])
    with_extras["trace"]["dialogue"] = [DIALOGUE]
    with_extras["trace"]["thoughts"] = ["I should find the book first."]
    with_extras["notes"] = {"top_candidates": scores, "rewrite": "find the book"}
    with_extras["timing"] = {"planning_seconds": 0}
    EpisodeRecord.from_json(with_extras)


def test_a_record_stored_without_a_trace_passes_with_only_its_extras() -> None:
    record = {**copy.deepcopy(GOOD[0]), "trace": {"dialogue": [DIALOGUE]}, "goal_conditions": {}, "hazards": []}
    assert EpisodeRecord.from_json(record).trace == {"dialogue": [DIALOGUE]}
    with pytest.raises(RecordError, match=r"trace.dialogue\[0\].step"):
        EpisodeRecord.from_json({**record, "trace": {"dialogue": [{**DIALOGUE, "step": "1"}]}})


@pytest.mark.parametrize(
    "argv",
    [
        ["view", "{run}", "--out", "{tmp}/viewer"],
        ["sample-errors", "{run}", "--out", "{tmp}/sample.json"],
        ["report", "{run}", "--bootstrap", "0", "--out", "{tmp}/report"],
        ["leaderboard", "{run}", "--bootstrap", "0", "--out", "{tmp}/board"],
        ["pack", "{run}"],
    ],
)
@pytest.mark.parametrize(
    ("change", "field"),
    [
        (_set("trace.dialogue", [[1, 2]]), "trace.dialogue[0]"),
        (_set("trace.dialogue", [{**DIALOGUE, "step": 1e400}]), "trace.dialogue[0].step"),
        (_set("hazards", ["fire", "flood"]), "hazards[0]"),
        (_set("trace.steps.0.index", "abc"), "trace.steps[0].index"),
    ],
)
def test_every_command_reading_records_gives_the_same_one_line(
    argv: list[str],
    change: Callable[[dict[str, Any]], None],
    field: str,
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
) -> None:
    records = copy.deepcopy(GOOD)
    change(records[2])
    run = _run(tmp_path / "run", records)
    code = main([a.format(run=run, tmp=tmp_path) for a in argv])
    error = capsys.readouterr().err.strip()
    assert code == 2, error
    assert len(error.splitlines()) == 1 and "unexpected" not in error
    assert f"{run / 'episodes.jsonl'}, line 3" in error and f"field '{field}'" in error
