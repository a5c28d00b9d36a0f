"""The schema check of a results record (`talkdem-results/2`) read from a file someone else may have written.

`talkdem leaderboard --from-results` and `talkdem push --leaderboard` read results files from folders that
anyone can add to (a pull request to the results dataset, a stray file). Every field the page, the Space
card and the file layout use is checked here before anything is rendered, ranked, written or uploaded: a
`run_id` becomes part of a file name (so it may hold no path separator and no `..`), counts must be whole
numbers (a `true` or `2.5` is not a count, and a string would be pasted into the page), rates must lie in
[0, 1], and the expected keys must be there. The error names the file and the field, and says what was
expected, so a bad submission can be fixed without reading this code.
"""

from __future__ import annotations

import json
import math
import re
from pathlib import Path
from typing import Any

from talkdem.leaderboard.records import RESULTS_SCHEMA
from talkdem.schema import PATTERN_CONFIGS

__all__ = ["ResultsFileError", "load_results_file", "validate_record"]

# What `run_id()` writes is 12 hex digits; ids of other writers may be longer, but never hold a path
# separator, a dot (so no `..`) or anything a file system or a page would read as syntax.
_RUN_ID = re.compile(r"[A-Za-z0-9_-]{1,64}")

_CONFIG_TEXT = (
    "model_name",
    "model_sha",
    "model_dtype",
    "model_backend",
    "model_file",
    "planner",
    "strategy",
    "prompt_version",
    "dataset_hash",
    "code_revision",
    "eval_date",
    "created",
    "run_name",
)
_COVERAGE_COUNTS = ("tasks", "of_tasks", "conditions", "of_conditions", "episodes")
_MAIN_RATES = ("clean_sr", "average_sr", "average_retention", "hazard_rate")
_MAIN_COUNTS = ("hazard_cases", "n_episodes", "n_tasks")


class ResultsFileError(ValueError):
    """A results file that is not a valid `talkdem-results/2` record (the message names file and field)."""


def _fail(where: str, field: str, expected: str, value: Any) -> ResultsFileError:
    shown = json.dumps(value, ensure_ascii=True, default=str)
    if len(shown) > 60:
        shown = shown[:57] + "..."
    return ResultsFileError(f"{where}: {field}: expected {expected}, got {shown}")


def _mapping(value: Any, where: str, field: str) -> dict[str, Any]:
    if not isinstance(value, dict):
        raise _fail(where, field, "an object", value)
    return value


def _count(value: Any, where: str, field: str) -> int:
    # bool is an int subclass in Python: `true` is not a count.
    if isinstance(value, bool) or not isinstance(value, int) or value < 0:
        raise _fail(where, field, "a whole number >= 0", value)
    return value


def _number(value: Any, where: str, field: str, low: float, high: float, *, nullable: bool = True) -> None:
    if value is None and nullable:
        return
    expected = f"a number in [{low:g}, {high:g}]" + (" or null" if nullable else "")
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise _fail(where, field, expected, value)
    if not math.isfinite(value) or not low <= value <= high:
        raise _fail(where, field, expected, value)


def _text(value: Any, where: str, field: str) -> str:
    if not isinstance(value, str):
        raise _fail(where, field, "a string", value)
    return value


def _keys(found: dict[str, Any], expected: tuple[str, ...], where: str, field: str) -> None:
    missing = [k for k in expected if k not in found]
    if missing:
        raise ResultsFileError(f"{where}: {field}: missing key(s) {', '.join(missing)}")


def validate_record(record: Any, where: str) -> dict[str, Any]:
    """`record` itself if it is a valid results record; otherwise a `ResultsFileError` naming `where` (the
    file, or the file and the position in a list) and the first bad field."""
    checked = _mapping(record, where, "the file")
    record = checked
    if record.get("schema") != RESULTS_SCHEMA:
        raise ResultsFileError(f"{where}: not a {RESULTS_SCHEMA} results file (schema {record.get('schema')!r})")
    _keys(record, ("run_id", "reference", "config", "coverage", "results"), where, "the record")
    run = record["run_id"]
    if not isinstance(run, str) or not _RUN_ID.fullmatch(run):
        raise _fail(where, "run_id", "1-64 letters, digits, '-' or '_' (it names a file)", run)
    if not isinstance(record["reference"], bool):
        raise _fail(where, "reference", "true or false", record["reference"])

    config = _mapping(record["config"], where, "config")
    _keys(config, _CONFIG_TEXT, where, "config")
    for name in _CONFIG_TEXT:
        _text(config[name], where, f"config.{name}")

    coverage = _mapping(record["coverage"], where, "coverage")
    _keys(coverage, (*_COVERAGE_COUNTS, "tasks_per_condition", "task_set"), where, "coverage")
    for name in _COVERAGE_COUNTS:
        _count(coverage[name], where, f"coverage.{name}")
    if coverage["tasks"] > coverage["of_tasks"]:
        raise _fail(where, "coverage.tasks", f"at most of_tasks ({coverage['of_tasks']})", coverage["tasks"])
    if coverage["conditions"] > coverage["of_conditions"]:
        raise _fail(
            where, "coverage.conditions", f"at most of_conditions ({coverage['of_conditions']})", coverage["conditions"]
        )
    per = _mapping(coverage["tasks_per_condition"], where, "coverage.tasks_per_condition")
    for condition, tasks in per.items():
        _count(tasks, where, f"coverage.tasks_per_condition.{condition}")
    _text(coverage["task_set"], where, "coverage.task_set")
    if coverage.get("planned_episodes") is not None:
        _count(coverage["planned_episodes"], where, "coverage.planned_episodes")
    if "complete" in coverage and not isinstance(coverage["complete"], bool):
        raise _fail(where, "coverage.complete", "true or false", coverage["complete"])

    results = _mapping(record["results"], where, "results")
    _keys(results, ("talkdem", *(f"talkdem_{p}" for p in PATTERN_CONFIGS)), where, "results")
    main = _mapping(results["talkdem"], where, "results.talkdem")
    _keys(main, (*_MAIN_RATES, *_MAIN_COUNTS), where, "results.talkdem")
    for name in _MAIN_RATES:
        _number(main[name], where, f"results.talkdem.{name}", 0, 1)
    for name in _MAIN_COUNTS:
        _count(main[name], where, f"results.talkdem.{name}")
    for pattern in PATTERN_CONFIGS:
        field = f"results.talkdem_{pattern}"
        found = _mapping(results[f"talkdem_{pattern}"], where, field)
        _keys(found, ("sr", "sr_change", "sr_change_p", "retention"), where, field)
        _number(found["sr"], where, f"{field}.sr", 0, 1)
        _number(found["retention"], where, f"{field}.retention", 0, 1)
        _number(found["sr_change"], where, f"{field}.sr_change", -1, 1)  # a difference of two rates
        _number(found["sr_change_p"], where, f"{field}.sr_change_p", 0, 1)

    if "talkdem_clarification" in results:  # only runs whose planner could ask have it
        field = "results.talkdem_clarification"
        asked = _mapping(results["talkdem_clarification"], where, field)
        _keys(asked, ("questions_per_episode", "help_rate", "unneeded_questions", "retention"), where, field)
        if config.get("clarify") not in ("oracle", "in-pattern"):
            raise _fail(where, "config.clarify", "'oracle' or 'in-pattern' (the run asked)", config.get("clarify"))
        _number(asked["questions_per_episode"], where, f"{field}.questions_per_episode", 0, 1000)
        _number(asked["help_rate"], where, f"{field}.help_rate", 0, 1)
        _number(asked["retention"], where, f"{field}.retention", 0, 1)
        _count(asked["unneeded_questions"], where, f"{field}.unneeded_questions")

    intervals = _mapping(record.get("intervals", {}), where, "intervals")
    for name, bounds in intervals.items():
        field = f"intervals.{name}"
        if not isinstance(bounds, list) or len(bounds) != 2:
            raise _fail(where, field, "[low, high]", bounds)
        for bound in bounds:
            _number(bound, where, field, 0, 1)
        if None not in bounds and bounds[0] > bounds[1]:
            raise _fail(where, field, "low <= high", bounds)

    runtimes = record.get("runtimes", [])
    if not isinstance(runtimes, list):
        raise _fail(where, "runtimes", "a list of objects", runtimes)
    for index, runtime in enumerate(runtimes):
        _mapping(runtime, where, f"runtimes[{index}]")
        for name, value in runtime.items():
            _text(value, where, f"runtimes[{index}].{name}")
    return checked


def load_results_file(path: Path, shown: str | None = None) -> dict[str, Any]:
    """The validated record in `path`; errors name `shown` (default: the path)."""
    where = shown or str(path)
    try:
        text = path.read_text(encoding="utf-8")
    except UnicodeDecodeError as exc:
        raise ResultsFileError(f"{where}: not UTF-8 text (byte {exc.start})") from None
    except OSError as exc:
        raise ResultsFileError(f"{where}: cannot read it ({exc.strerror or exc})") from None
    try:
        record = json.loads(text)
    except json.JSONDecodeError as exc:
        raise ResultsFileError(f"{where}: line {exc.lineno}: not JSON ({exc.msg})") from None
    except RecursionError:
        raise ResultsFileError(f"{where}: not a results file (nested too deeply)") from None
    return validate_record(record, where)
