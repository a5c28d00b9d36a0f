"""The leaderboard folder: a static Hugging Face Space as it stands.

    OUT/README.md          Space card (front matter `sdk: static`) with the standings and how to submit
    OUT/index.html         the page (self-contained)
    OUT/leaderboard.json   every record on the page
    OUT/results/README.md  card of the results dataset (`talkdem push --results-repo`)
    OUT/results/<model>/results_<date>_<run id>.json   one record per run (the Hub template's layout)

Results files already in `OUT/results` stay and are shown: a board grows run by run.
"""

from __future__ import annotations

import json
import re
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from talkdem.leaderboard.page import SUBMIT_STEPS, render_html
from talkdem.leaderboard.ranking import RANK_KEY, rank_records
from talkdem.leaderboard.records import RESULTS_SCHEMA, results_record
from talkdem.leaderboard.validate import ResultsFileError, load_results_file
from talkdem.paths import file_stem
from talkdem.report.coverage import Coverage
from talkdem.report.runs import ScoredRun, strategy_label
from talkdem.report.table import markdown_cell, markdown_text

__all__ = ["SPACE_FRONT_MATTER", "read_results", "results_path", "write_leaderboard", "write_space"]

SPACE_FRONT_MATTER = {
    "title": "TALK-Dem Leaderboard",
    "emoji": "🧭",
    "colorFrom": "blue",
    "colorTo": "indigo",
    "sdk": "static",
    "app_file": "index.html",
    "pinned": False,
    "license": "mit",
    "short_description": "Robot task planning under dementia-associated speech",
    "tags": ["leaderboard", "robotics", "task-planning", "benchmark"],
}


_SAFE_ID = re.compile(r"[A-Za-z0-9_-]{1,64}")


def _slug(text: str) -> str:
    # Bounded (`file_stem`): a model with a very long name still gets a folder the file system takes.
    return file_stem(text, "model")


def results_path(record: dict[str, Any]) -> Path:
    """`<model>/results_<date>_<run id>.json`: the run id keeps runs apart whose names differ only in
    punctuation; the same run always lands on the same file."""
    created = re.sub(r"[^0-9T]+", "-", record["config"].get("created", "")[:19]).strip("-") or "undated"
    if not isinstance(record["run_id"], str) or not _SAFE_ID.fullmatch(record["run_id"]):
        # Checked again here, whoever built the record: the id is part of the path written under --out.
        raise ResultsFileError(f"run_id {record['run_id']!r}: not a results id (letters, digits, '-', '_')")
    return Path(_slug(record["config"]["model_name"])) / f"results_{created}_{record['run_id']}.json"


def read_results(folder: Path) -> list[dict[str, Any]]:
    """Every results record under `folder` (recursively), each checked against the schema
    (`talkdem.leaderboard.validate`); a bad file is an error naming it (as `folder/relative path`) and its
    first bad field. Two files with the same `run_id` are refused: one run would be shown twice."""
    records: list[dict[str, Any]] = []
    seen: dict[str, str] = {}
    for path in sorted(folder.rglob("*.json")):
        shown = str(folder / path.relative_to(folder))
        record = load_results_file(path, shown)
        if record["run_id"] in seen:
            raise ResultsFileError(f"{shown}: run_id {record['run_id']} is also in {seen[record['run_id']]}")
        seen[record["run_id"]] = shown
        records.append(record)
    return records


def _front_matter() -> str:
    lines = ["---"]
    for key, value in SPACE_FRONT_MATTER.items():
        if isinstance(value, list):
            lines.append(f"{key}:")
            lines += [f"- {v}" for v in value]
        elif isinstance(value, bool):
            lines.append(f"{key}: {'true' if value else 'false'}")
        else:
            lines.append(f"{key}: {value}")
    return "\n".join([*lines, "---"]) + "\n"


def _standings_markdown(records: Sequence[dict[str, Any]]) -> str:
    standings = rank_records(records)
    out = []
    for group in standings.groups:
        out.append(f"### Runs over {Coverage.from_json(group.coverage).describe()}\n")
        out.append("| Rank | Model | Strategy | Planner | Avg SR | Avg retention | Clean SR | Date |")
        out.append("|---:|---|---|---|---:|---:|---:|---|")
        for rank, record in group.ranked:
            c, m = record["config"], record["results"]["talkdem"]
            cells = (
                str(rank),
                c["model_name"],
                strategy_label(c["strategy"]),
                c["planner"],
                *(
                    "–" if m[k] is None else f"{100 * m[k]:.1f}"
                    for k in ("average_sr", "average_retention", "clean_sr")
                ),
                c.get("eval_date") or "–",
            )
            out.append("| " + " | ".join(markdown_cell(x) for x in cells) + " |")
        out.append("")
    if standings.reference:
        names = ", ".join(
            f"{markdown_text(r['config']['model_name'])} ({Coverage.from_json(r['coverage']).describe()})"
            for r in standings.reference
        )
        out.append(f"Reference plans (not ranked): {names}.\n")
    return "\n".join(out)


def _space_readme(records: Sequence[dict[str, Any]]) -> str:
    steps = "\n".join(f"{i}. **{h}.** {t}" for i, (h, t) in enumerate(SUBMIT_STEPS, start=1))
    return (
        _front_matter() + "\n# TALK-Dem leaderboard\n\n"
        "Robot task planning under dementia-associated communication. The page (`index.html`) ranks runs by "
        f"the {RANK_KEY}, only against runs over the same episodes; reference plans are shown apart.\n\n"
        f"## Standings\n\n{_standings_markdown(records)}\n"
        f"## How to submit a run\n\n{steps}\n\n"
        "## Results files\n\n"
        f"`results/<model>/results_<date>_<run id>.json`, schema `{RESULTS_SCHEMA}`: the Hub leaderboard "
        "template's fields (`config.model_name`, `config.model_sha`, `config.model_dtype`, "
        "`results: {task: {metric: value}}`, rates as fractions) plus coverage, 95% bootstrap intervals and "
        "provenance (planner, strategy, prompt version, dataset hash, code revision, date, and where recorded "
        "the runtime of each sitting: CPU and model library build).\n"
    )


_RESULTS_CARD = """---
pretty_name: TALK-Dem leaderboard results
license: mit
tags:
- leaderboard
- robotics
- task-planning
---

# TALK-Dem leaderboard results

One JSON file per run: `<model>/results_<date>_<run id>.json`, schema `{schema}`. Each file carries the Hub
leaderboard template's fields (`config.model_name`, `config.model_sha`, `config.model_dtype`,
`results: {{task: {{metric: value}}}}`, rates as fractions) and TALK-Dem's own: coverage (tasks per condition),
95% bootstrap intervals, planner, strategy, prompt version, dataset hash, code revision and date, and, where
the run recorded it, `runtimes`: the CPU and model library build of each sitting (llama.cpp scores move with them).
Rebuild the leaderboard page with `talkdem leaderboard --from-results . --out board`.
"""


def write_space(records: Sequence[dict[str, Any]], out: Path, viewer: str | None = None) -> list[Path]:
    """Write the Space folder for these records (results files included); returns the files written.
    `viewer`: a link to the episode viewer (`talkdem view`) for the page."""
    results = out / "results"
    results.mkdir(parents=True, exist_ok=True)
    written = []
    for record in records:
        path = results / results_path(record)
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(record, indent=2, ensure_ascii=False) + "\n", encoding="utf-8")
        written.append(path)
    (results / "README.md").write_text(_RESULTS_CARD.format(schema=RESULTS_SCHEMA), encoding="utf-8")
    (out / "leaderboard.json").write_text(json.dumps(list(records), indent=2, ensure_ascii=False) + "\n", "utf-8")
    (out / "README.md").write_text(_space_readme(records), encoding="utf-8")
    (out / "index.html").write_text(render_html(records, viewer=viewer), encoding="utf-8")
    return [*written, results / "README.md", out / "leaderboard.json", out / "README.md", out / "index.html"]


def write_leaderboard(runs: Sequence[ScoredRun], out: Path, viewer: str | None = None) -> list[Path]:
    """The Space folder for `runs` plus the results already in `out/results`; returns the files written
    (`out/index.html` last but one, `out/README.md`... see `write_space`)."""
    fresh = [results_record(run) for run in runs]
    kept = []
    if (out / "results").is_dir():
        new_ids = {r["run_id"] for r in fresh}
        kept = [r for r in read_results(out / "results") if r["run_id"] not in new_ids]
    return write_space([*kept, *fresh], out, viewer=viewer)
