"""Write the viewer folder: a static page that works from file:// and as a static Space (no server).

    OUT/index.html             the page (inline style and script)
    OUT/README.md              a static Space's card (the folder uploads as a Space as it is)
    OUT/data/index.js          one compact row per episode: what the table, the filters and the search need
    OUT/data/chunk-NNNN.js     the details of `chunk_size` consecutive episodes, loaded when one is opened

Browsers refuse fetch() and XHR of file:// URLs, so the data are scripts that hand their JSON to the page
(`TALKDEM_VIEWER_INDEX = ...`, `TALKDEM_VIEWER_CHUNK(n, ...)`). JSON inside a script is escaped so that
no string can end the script (`</script>`), open a comment or break a line in JavaScript. Published data
name runs by label and run-directory name, never by machine path.
"""

from __future__ import annotations

import hashlib
import json
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from talkdem.metrics.errors import ERROR_LABELS, ErrorType
from talkdem.report.public import public_config, public_model
from talkdem.report.runs import strategy_label
from talkdem.schema import PATTERNS
from talkdem.sim.hazards import HazardCategory
from talkdem.viewer.diff import word_diff
from talkdem.viewer.episodes import ViewedEpisode, ViewedRun
from talkdem.viewer.labels import TYPE_NAMES

__all__ = ["VIEWER_SCHEMA", "ViewerFiles", "script_json", "write_viewer"]

VIEWER_SCHEMA = "talkdem-viewer/1"
_INDEX_PREFIX = f"/* {VIEWER_SCHEMA} */\nwindow.TALKDEM_VIEWER_INDEX = "


@dataclass
class ViewerFiles:
    """What `write_viewer` wrote."""

    folder: Path
    page: Path
    index: Path
    chunks: list[Path] = field(default_factory=list)
    episodes: int = 0
    sampled: int = 0


def script_json(value: Any) -> str:
    """JSON that is safe inside an HTML <script>: `<`, `>` and `&` as \\u escapes (no `</script>` or
    `<!--` can appear), and the two line separators JavaScript once refused in strings escaped too."""
    text = json.dumps(value, ensure_ascii=False, separators=(",", ":"), allow_nan=False)
    for char in ("<", ">", "&", "\u2028", "\u2029"):
        text = text.replace(char, f"\\u{ord(char):04x}")
    return text


def _run_info(run: ViewedRun) -> dict[str, Any]:
    model = public_model(run.header.model)
    return {
        "label": run.label,
        "key": run.key,
        "run_dir": run.run_dir.name,
        "model": model["name"],
        "revision": model["revision"][:12],
        "strategy": strategy_label(run.header.strategy),
        "planner": run.header.planner,
        "created": run.header.created[:10],
        "code_revision": run.header.code_revision[:12],
        "dataset_hash": run.header.dataset_hash[:12],
        "episodes": len(run.episodes),
    }


def _row(run_index: int, episode: ViewedEpisode, clean_row: int, sampled: bool) -> list[Any]:
    record = episode.record
    return [
        run_index,
        record.episode_id,
        record.pattern,
        record.level,
        int(episode.success),
        " ".join(dict.fromkeys(episode.hazards)),
        episode.error.type.value if episode.error else "",
        episode.plan_length,
        -1 if episode.clean_solved is None else int(episode.clean_solved),
        int(sampled),
        clean_row,
        record.instruction,
    ]


_ROW_FIELDS = (
    "run",
    "episode_id",
    "pattern",
    "level",
    "success",
    "hazards",
    "error",
    "plan_length",
    "clean_solved",
    "sampled",
    "clean_row",
    "instruction",
)


def _number(value: Any) -> float | None:
    """A finite number, else None (JSON has no infinity: a masked skill's -inf score shows as unknown)."""
    if not isinstance(value, int | float) or isinstance(value, bool):
        return None
    try:
        return float(value) if math.isfinite(value) else None
    except OverflowError:  # an integer too large for a float
        return None


def _top(notes: dict[str, str]) -> list[list[list[Any]]] | None:
    """`talkdem run --log-top N` keeps each step's best candidates in the record's notes (JSON text)."""
    text = notes.get("top_candidates")
    if not text:
        return None
    try:
        steps = json.loads(text)
    except (ValueError, RecursionError):  # checked when the record was read; kept safe for records made in code
        return None
    if not isinstance(steps, list):
        return None
    out = []
    for step in steps:
        if not isinstance(step, list):
            return None
        out.append([[str(c[0]), _number(c[1])] for c in step if isinstance(c, list) and len(c) == 2])
    return out


def _detail(episode: ViewedEpisode) -> dict[str, Any]:
    record = episode.record
    trace = record.trace
    steps = [
        [str(s.get("skill", "")), int(bool(s.get("ok"))), str(s.get("message") or ""), str(s.get("failure") or "")]
        for s in trace.get("steps", [])
        if isinstance(s, dict)
    ]
    goal = trace.get("goal", {})
    goals = [
        [str(c.get("name", "")), int(bool(c.get("met")))]
        for c in (goal.get("conditions", []) if isinstance(goal, dict) else [])
        if isinstance(c, dict)
    ]
    hazards = [
        [str(h.get("category", "")), h.get("step") if isinstance(h.get("step"), int) else None]
        for h in trace.get("hazards", record.hazards)
        if isinstance(h, dict)
    ]
    notes = {k: v for k, v in public_config(record.notes).items() if k != "top_candidates" and v}
    # A clarification run's exchanges: [actions done when asked, question, slot ("" unmatched), answer, in pattern].
    dialogue = [
        [
            int(x.get("step", 0)),
            str(x.get("question", "")),
            str(x.get("slot", "")),
            str(x.get("answer", "")),
            int(bool(x.get("in_pattern"))),
        ]
        for x in trace.get("dialogue", [])
        if isinstance(x, dict)
    ]
    diff = None
    if record.pattern != "clean" and episode.clean_text:
        diff = [list(segment) for segment in word_diff(episode.clean_text, record.instruction)]
    return {
        "shown": record.instruction_shown,
        "diff": diff,
        "steps": steps,
        "dialogue": dialogue if "dialogue" in trace else None,
        "end": str(trace.get("end_reason", "")),
        "goals": goals,
        "met": record.goal_conditions.get("met"),
        "total": record.goal_conditions.get("total"),
        "hazards": hazards,
        "top": _top(record.notes),
        "notes": notes,
        "seconds": _number(record.timing.get("planning_seconds")),
        "stored_success": record.success,
        "reason": episode.error.reason if episode.error else "",
    }


def _starts_with(path: Path, prefix: bytes) -> bool:
    with path.open("rb") as handle:
        return handle.read(len(prefix)) == prefix


def _check_folder(out: Path) -> None:
    """Write only into a new or empty folder or one this command wrote before (its old chunks are replaced)."""
    if not out.exists():
        return
    if not out.is_dir():
        raise ValueError(f"{out}: exists and is not a folder")
    index = out / "data" / "index.js"
    # Only the start is read: whatever else the folder's index.js holds, it says whether this command wrote it.
    ours = index.is_file() and _starts_with(index, _INDEX_PREFIX.encode())
    if any(out.iterdir()) and not ours:
        raise ValueError(f"{out}: not empty and not a viewer folder written by `talkdem view` (give a new --out)")
    for old in (out / "data").glob("chunk-*.js"):
        old.unlink()


def _sample_keys(runs: Sequence[ViewedRun], sample: dict[str, Any] | None) -> set[tuple[int, str]]:
    """(run position, episode id) of each sampled failure. An entry names its run by key (`run_key`), which
    does not depend on the runs shown together or their order; samples written before keys, by label."""
    if sample is None:
        return set()
    by_key = {run.key: i for i, run in enumerate(runs)}
    by_label = {run.label: i for i, run in enumerate(runs)}
    episodes = [{e.episode_id: e for e in run.episodes} for run in runs]
    keys = set()
    for n, entry in enumerate(sample["episodes"], start=1):
        key = entry.get("run_key") or ""
        found_run = by_key.get(key) if key else by_label.get(entry["run"])
        name = f"{entry['run']} / {entry['episode_id']}" + (f", run key {key}" if key else "")
        found = episodes[found_run].get(entry["episode_id"]) if found_run is not None else None
        if found_run is None or found is None:
            raise ValueError(
                f"error sample: episode {n} ({name}) is not among the runs given "
                "(give the runs the sample was drawn from)"
            )
        if not found.in_error_analysis:
            raise ValueError(f"error sample: episode {n} ({name}) is not a failure solved clean")
        keys.add((found_run, entry["episode_id"]))
    return keys


def write_viewer(
    runs: Sequence[ViewedRun],
    out: Path,
    *,
    sample: dict[str, Any] | None = None,
    chunk_size: int = 200,
    title: str = "TALK-Dem episodes",
) -> ViewerFiles:
    """Write the viewer of `runs` into `out` (see the module docstring); `sample`: an error sample
    (`talkdem sample-errors`) whose failures the page offers for labelling first."""
    from talkdem.tasks import get_task
    from talkdem.viewer.page import render_page

    if chunk_size < 1:
        raise ValueError(f"chunk size must be at least 1, got {chunk_size}")
    if not runs or not any(run.episodes for run in runs):
        raise ValueError("no episodes to view")
    _check_folder(out)
    sampled = _sample_keys(runs, sample)
    (out / "data").mkdir(parents=True, exist_ok=True)
    episodes = [(i, e) for i, run in enumerate(runs) for e in run.episodes]
    position = {(i, e.episode_id): n for n, (i, e) in enumerate(episodes)}
    rows, tasks = [], {}
    for i, episode in episodes:
        record = episode.record
        clean_row = position.get((i, f"{record.task_id}:clean:0"), -1)
        rows.append(_row(i, episode, clean_row, (i, episode.episode_id) in sampled))
        if record.task_id not in tasks:
            task = get_task(record.task_id)
            tasks[record.task_id] = {
                "type": task.task_type,
                "clean": episode.clean_text,
                "reference": list(task.reference_plan),
            }
    identity = hashlib.sha256(
        json.dumps([[r.label, r.key, r.run_dir.name, len(r.episodes)] for r in runs]).encode()
    ).hexdigest()[:12]
    index = {
        "schema": VIEWER_SCHEMA,
        "id": identity,
        "title": title,
        "chunk_size": chunk_size,
        "chunks": (len(rows) + chunk_size - 1) // chunk_size,
        "fields": list(_ROW_FIELDS),
        "runs": [_run_info(run) for run in runs],
        "patterns": {config: [p.name, p.abbreviation] for config, p in PATTERNS.items()},
        "types": [[t.value, TYPE_NAMES[t], ERROR_LABELS[t]] for t in ErrorType],
        "hazard_categories": [c.value for c in HazardCategory],
        "tasks": tasks,
        "sample": None
        if sample is None
        else {"seed": sample.get("seed"), "per_condition": sample.get("per_condition"), "n": len(sampled)},
        "rows": rows,
    }
    files = ViewerFiles(out, out / "index.html", out / "data" / "index.js", episodes=len(rows), sampled=len(sampled))
    files.index.write_text(_INDEX_PREFIX + script_json(index) + ";\n", encoding="utf-8")
    for number, start in enumerate(range(0, len(episodes), chunk_size)):
        details = [_detail(e) for _, e in episodes[start : start + chunk_size]]
        path = out / "data" / f"chunk-{number:04d}.js"
        path.write_text(f"window.TALKDEM_VIEWER_CHUNK({number},{script_json(details)});\n", encoding="utf-8")
        files.chunks.append(path)
    files.page.write_text(render_page(title), encoding="utf-8")
    (out / "README.md").write_text(_SPACE_CARD.format(title=title, n=len(rows), runs=len(runs)), encoding="utf-8")
    return files


_SPACE_CARD = """---
title: {title}
sdk: static
app_file: index.html
pinned: false
---

# {title}

{n} episodes of {runs} TALK-Dem run(s), written by `talkdem view`: filter and search the table, open an
episode (instruction against its clean control, the plan step by step with the simulator's feedback, goal
conditions, hazards, the reference plan) and label failures with the paper's six error types. Labels stay in
the browser until exported; `talkdem report RUN_DIR... --labels FILE` compares them with the automatic
classifier.
"""
