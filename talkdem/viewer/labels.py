"""Error types given by people (exported from the viewer) against the automatic classifier: the paper's
error-by-pattern table from the human labels, Cohen's kappa and the confusion matrix.

A labels file (what the viewer's Export writes):

    {"schema": "talkdem-error-labels/1",
     "labels": [{"run": "qwen2.5-coder-0.5b / CARE", "run_key": "1a2b3c4d", "episode_id": "<task>:intrusion:3",
                 "type": "subgoal_omission", "automatic": "subgoal_omission"}, ...]}

`run_key` is the run's key (`talkdem.report.runs.run_key`), by which the entry is matched to a reported run:
a display label depends on the runs shown together, a key does not (files exported before keys existed are
matched by `run`, the run's label). `type` is one of the six `ErrorType` values. Every entry
is checked against the runs being reported: an unknown run or episode id, an episode that did not fail
under a pattern, an unknown type or a second label for one episode is refused with one line naming the
file and the entry. `automatic` is what the viewer showed; the agreement is computed against the
classifier run now on the re-executed plan, so a stale file cannot misreport it.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from talkdem.metrics import ERROR_LABELS, ErrorType, classify_error
from talkdem.report.runs import ScoredRun
from talkdem.report.table import PATTERN_LABELS, Table
from talkdem.schema import PATTERN_CONFIGS

__all__ = [
    "LABELS_SCHEMA",
    "TYPE_NAMES",
    "Agreement",
    "HumanLabel",
    "agreement",
    "cohen_kappa",
    "label_tables",
    "read_labels",
]

LABELS_SCHEMA = "talkdem-error-labels/1"

TYPE_NAMES = {
    ErrorType.REFERENT: "Referent Resolution",
    ErrorType.STATE: "State Interpretation",
    ErrorType.LOCATION: "Location / Receptacle",
    ErrorType.SUBGOAL: "Subgoal Omission",
    ErrorType.ORGANIZATION: "Plan Organization",
    ErrorType.EXECUTION: "Execution Failure",
}
"""The paper's names of the six types (appendix "Error Taxonomy")."""


@dataclass(frozen=True)
class HumanLabel:
    """One labelled failure, with the classifier's type for the same re-executed plan."""

    run: str
    episode_id: str
    pattern: str
    level: int
    human: ErrorType
    automatic: ErrorType


def _entry_name(n: int, entry: object) -> str:
    if isinstance(entry, dict) and isinstance(entry.get("episode_id"), str):
        return f"label {n} ({entry['episode_id']} of run '{entry.get('run', '?')}')"
    return f"label {n}"


def read_labels(path: Path, runs: Sequence[ScoredRun]) -> list[HumanLabel]:
    """The labels of `path`, checked against `runs` (see the module docstring)."""
    from talkdem.viewer.json_files import read_json_file

    name = str(path)  # in error messages; captions name the file alone
    data = read_json_file(path, "a labels file")
    if not isinstance(data, dict) or data.get("schema") != LABELS_SCHEMA:
        raise ValueError(f"{name}: not a labels file (expected a JSON object with schema {LABELS_SCHEMA!r})")
    entries = data.get("labels")
    if not isinstance(entries, list):
        raise ValueError(f"{name}: field 'labels' must be a list of labels")
    if not entries:
        raise ValueError(f"{name}: no labels (label failures in the viewer, then export)")
    by_run = {run.label: run for run in runs}
    by_key = {run.key: run.label for run in runs}
    results = {run.label: {e.instruction_id: e for e in run.scores.episodes} for run in runs}
    known_errors = {(e.run, e.instruction_id): e.type for run in runs for e in run.scores.errors}
    types = {t.value: t for t in ErrorType}
    seen: dict[tuple[str, str], int] = {}
    labels = []
    for n, entry in enumerate(entries, start=1):
        where = f"{name}: {_entry_name(n, entry)}"
        if not isinstance(entry, dict):
            raise ValueError(f"{where}: expected an object with 'run', 'episode_id' and 'type'")
        run, episode_id, kind = entry.get("run"), entry.get("episode_id"), entry.get("type")
        if not isinstance(run, str) or not isinstance(episode_id, str) or not isinstance(kind, str):
            raise ValueError(f"{where}: 'run', 'episode_id' and 'type' must be strings")
        key = entry.get("run_key")
        if key is not None:
            if not isinstance(key, str) or key not in by_key:
                known = ", ".join(f"{label} [{k}]" for k, label in by_key.items())
                raise ValueError(f"{where}: unknown run key {key!r} (the runs reported: {known})")
            run = by_key[key]  # the report's label of the run, whatever the viewer showed beside it
        elif run not in by_run:
            raise ValueError(f"{where}: unknown run '{run}' (the runs reported: {', '.join(by_run)})")
        result = results[run].get(episode_id)
        if result is None:
            raise ValueError(f"{where}: unknown episode id (not among the {len(results[run])} episodes of '{run}')")
        if kind not in types:
            raise ValueError(f"{where}: unknown type '{kind}' (expected one of {', '.join(types)})")
        if result.condition.is_clean or result.success:
            what = "a clean episode" if result.condition.is_clean else "an episode that succeeded"
            raise ValueError(f"{where}: {what}; only failures under a pattern take an error type")
        if (run, episode_id) in seen:
            raise ValueError(f"{where}: a second label for this episode (the first is label {seen[(run, episode_id)]})")
        seen[(run, episode_id)] = n
        automatic = known_errors.get((run, episode_id))
        if automatic is None:  # a failure whose clean twin failed too: classified on demand
            from talkdem.tasks import get_task

            assert result.trace is not None
            found = classify_error(get_task(result.task_id), result.trace)
            assert found is not None  # the episode failed
            automatic = found.type
        labels.append(
            HumanLabel(run, episode_id, result.condition.pattern, result.condition.level, types[kind], automatic)
        )
    return labels


@dataclass(frozen=True)
class Agreement:
    """How often people and the classifier give the same type."""

    n: int
    observed: float
    """Share of labels where the two agree."""
    kappa: float
    """Cohen's kappa; NaN when undefined (both gave one and the same type to every failure)."""
    confusion: dict[ErrorType, dict[ErrorType, int]]
    """human type -> automatic type -> count."""


def cohen_kappa(pairs: Sequence[tuple[ErrorType, ErrorType]]) -> float:
    """Cohen's kappa of two raters over the same items: (p_o - p_e) / (1 - p_e), with p_e from each rater's
    own type frequencies. NaN for no items, or when chance agreement is already 1."""
    n = len(pairs)
    if n == 0:
        return math.nan
    observed = sum(a == b for a, b in pairs) / n
    expected = sum((sum(a == t for a, _ in pairs) / n) * (sum(b == t for _, b in pairs) / n) for t in ErrorType)
    if math.isclose(expected, 1.0):
        return math.nan
    return (observed - expected) / (1 - expected)


def agreement(labels: Sequence[HumanLabel]) -> Agreement:
    pairs = [(label.human, label.automatic) for label in labels]
    confusion = {h: dict.fromkeys(ErrorType, 0) for h in ErrorType}
    for human, automatic in pairs:
        confusion[human][automatic] += 1
    observed = sum(a == b for a, b in pairs) / len(pairs) if pairs else math.nan
    return Agreement(len(pairs), observed, cohen_kappa(pairs), confusion)


def _kappa_text(value: float) -> str:
    return "undefined" if math.isnan(value) else f"{value:.2f}"


def label_tables(labels: Sequence[HumanLabel], source: str) -> list[Table]:
    """The paper's error-by-pattern table from human labels, the agreement with the classifier, and the
    confusion matrix. `source` names the labels file in captions (its file name, never a path)."""
    rows = []
    totals = dict.fromkeys(ErrorType, 0)
    for pattern in PATTERN_CONFIGS:
        counts = dict.fromkeys(ErrorType, 0)
        for label in labels:
            if label.pattern == pattern:
                counts[label.human] += 1
                totals[label.human] += 1
        rows.append((PATTERN_LABELS[pattern], *(str(counts[t]) for t in ErrorType), str(sum(counts.values()))))
    rows.append(("Total", *(str(totals[t]) for t in ErrorType), str(sum(totals.values()))))
    human = Table(
        "errors_human",
        "Error types across communication patterns (human labels)",
        f"Primary error type given by people to {len(labels)} failures labelled in the viewer ({source}), runs and "
        'levels pooled: the paper\'s Table "Error distribution across communication patterns" for these runs.',
        ("Condition", *(ERROR_LABELS[t] for t in ErrorType), "n"),
        tuple(rows),
    )
    found = agreement(labels)
    summary = Table(
        "errors_agreement",
        "Agreement of the human labels with the automatic classifier",
        "Cohen's kappa of the human and the automatic primary error type over the labelled failures (chance "
        "agreement from each rater's own type frequencies); observed agreement in %. The automatic type is the "
        "classifier's on the re-executed plan (talkdem/metrics/errors.py).",
        ("Labelled", "Agreement", "Cohen's kappa"),
        ((str(found.n), f"{100 * found.observed:.1f}", _kappa_text(found.kappa)),),
    )
    matrix_rows = []
    for human_type in ErrorType:
        counts = found.confusion[human_type]
        matrix_rows.append((TYPE_NAMES[human_type], *(str(counts[t]) for t in ErrorType), str(sum(counts.values()))))
    column_totals = [sum(found.confusion[h][t] for h in ErrorType) for t in ErrorType]
    matrix_rows.append(("Total", *(str(v) for v in column_totals), str(found.n)))
    matrix = Table(
        "errors_confusion",
        "Confusion matrix: human label (rows) against the automatic type (columns)",
        f"Counts of labelled failures; the diagonal is agreement (Cohen's kappa {_kappa_text(found.kappa)}, "
        f"n = {found.n}).",
        ("Human \\ automatic", *(ERROR_LABELS[t] for t in ErrorType), "n"),
        tuple(matrix_rows),
    )
    return [human, summary, matrix]
