"""The sample page: one HTML file with its style and script inlined, nothing fetched from the network.

The markup is written here, at write time: the word-level diff against the clean control (`talkdem.viewer`'s
`word_diff`) becomes `<mark>` and `<del>` elements, and every string from the data is HTML-escaped on the way
in, so an utterance cannot inject markup or script. The inlined script only shows and hides what is there."""

from __future__ import annotations

import html
from collections.abc import Sequence
from importlib import resources
from pathlib import Path

from talkdem.dataset_page.records import PageTask, PageVariant
from talkdem.files import replace_file
from talkdem.schema import LEVELS, PATTERN_CONFIGS, PATTERNS
from talkdem.viewer import word_diff

__all__ = ["render_sample_page", "write_sample_page"]

TITLE = "TALK-Dem: a sample of the dataset"


def _asset(name: str) -> str:
    text = resources.files("talkdem.dataset_page").joinpath("assets", name).read_text(encoding="utf-8")
    # Inlined into the page: a closing tag inside would end the element early.
    if "</script" in text.lower() or "</style" in text.lower():
        raise ValueError(f"asset {name} holds a closing tag and cannot be inlined")
    return text


def _e(text: str) -> str:
    return html.escape(text, quote=True)


def _highlighted(clean: str, text: str) -> str:
    parts = []
    for kind, words in word_diff(clean, text):
        if kind == "ins":
            parts.append(f'<mark class="ins">{_e(words)}</mark>')
        elif kind == "del":
            # Dropped clean words are shown where they were, set apart so the utterance still reads.
            parts.append(f'<del class="del" title="in the clean control, not here">{_e(words)}</del> ')
        else:
            parts.append(_e(words))
    return "".join(parts)


def _cell(task: PageTask, variant: PageVariant | None, level: int) -> str:
    if variant is None:
        return f'<td data-level="{level}" class="missing">not in this build</td>'
    badge = ""
    if not variant.passed:
        checks = ", ".join(variant.failed_checks) or "unnamed"
        badge = f'<div class="failed">kept with failed checks: {_e(checks)}</div>'
    return f'<td data-level="{level}"><div class="utt">{_highlighted(task.clean, variant.text)}</div>{badge}</td>'


def _task_section(task: PageTask) -> str:
    by_cell = {(v.pattern, v.level): v for v in task.variants}
    heads = "".join(f'<th scope="col" data-level="{level}">Level {level}</th>' for level in LEVELS)
    rows = []
    for config in PATTERN_CONFIGS:
        pattern = PATTERNS[config]
        cells = "".join(_cell(task, by_cell.get((config, level)), level) for level in LEVELS)
        rows.append(
            f'<tr data-pattern="{config}"><th scope="row" title="{_e(pattern.definition)}">{_e(pattern.name)} '
            f'<span class="abbr">{_e(pattern.abbreviation)}</span></th>{cells}</tr>'
        )
    target = f" · target {_e(task.target)}" if task.target else ""
    return (
        f'<section class="task" data-type="{_e(task.task_type)}" id="{_e(task.task_id)}">'
        f'<h2><span class="tid">{_e(task.task_id)}</span> <span class="ttype">{_e(task.task_type)}</span>'
        f'<span class="target">{target}</span></h2>'
        f'<dl class="given"><dt>Seed (ALFRED annotation)</dt><dd class="seed">{_e(task.seed)}</dd>'
        f'<dt>Clean control</dt><dd class="clean">{_e(task.clean)}</dd></dl>'
        f'<table class="variants"><thead><tr><th scope="col">Pattern</th>{heads}</tr></thead>'
        f"<tbody>{''.join(rows)}</tbody></table></section>"
    )


def _options(select_id: str, label: str, every: str, values: Sequence[tuple[str, str]]) -> str:
    options = "".join(f'<option value="{_e(v)}">{_e(text)}</option>' for v, text in values)
    return f'<label>{label} <select id="{select_id}"><option value="">{every}</option>{options}</select></label>'


def render_sample_page(tasks: Sequence[PageTask], total_tasks: int, per_type: int | None) -> str:
    """The page for `tasks` (drawn from `total_tasks`, `per_type` per task type, or all when `None`)."""
    if not tasks:
        raise ValueError("no tasks to show")
    types = sorted({t.task_type for t in tasks})
    if per_type is None:
        chosen = f"All {len(tasks):,} tasks of the dataset."
    else:
        chosen = (
            f"{len(tasks):,} of the dataset's {total_tasks:,} tasks: {per_type} per task type, evenly spaced in "
            "task-id order (<code>talkdem sample-page DATA_DIR --tasks all</code> writes every task)."
        )
    made = sorted({(t.generator, t.prompt_version) for t in tasks})
    made_by = "; ".join(f"generator <code>{_e(g)}</code>, version <code>{_e(v)}</code>" for g, v in made)
    filters = (
        '<input id="search" type="search" placeholder="Search tasks (id, words)" aria-label="search tasks">'
        + _options("f-pattern", "Pattern", "All patterns", [(c, PATTERNS[c].name) for c in PATTERN_CONFIGS])
        + _options("f-level", "Level", "All levels", [(str(lv), f"Level {lv}") for lv in LEVELS])
        + _options("f-type", "Task type", "All task types", [(t, t) for t in types])
        + '<span id="count" aria-live="polite"></span>'
    )
    return (
        '<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
        '<meta name="viewport" content="width=device-width, initial-scale=1">'
        f"<title>{TITLE}</title><style>{_asset('page.css')}</style></head><body>"
        f'<header><h1>{TITLE}</h1><p id="summary">{chosen} Each task: its ALFRED seed, the clean '
        "control written from it, and the 15 variants (five patterns, three levels), each generated "
        f"independently from the clean control. Made by {made_by}.</p>"
        '<p class="legend"><mark class="ins">highlighted</mark>: words the variant adds to the clean control '
        '(a word-level diff); <del class="del">struck</del>: words of the clean control it drops or replaces. '
        "Not for clinical use: synthetic utterances, not the speech of people living with dementia.</p></header>"
        f'<div id="controls">{filters}</div>'
        f'<main id="tasks">{"".join(_task_section(t) for t in tasks)}</main>'
        '<p id="none" hidden>No task matches the filters.</p>'
        f"<script>{_asset('page.js')}</script></body></html>\n"
    )


def write_sample_page(tasks: Sequence[PageTask], total_tasks: int, out: Path, per_type: int | None = 5) -> Path:
    """Write the page to `out` (atomically: a reader never sees half a page)."""
    if out.is_dir():
        raise ValueError(f"{out}: is a folder; give the HTML file to write (e.g. {out / 'sample.html'})")
    if not out.parent.is_dir():
        raise ValueError(f"{out.parent}: no such folder to write the page into")
    text = render_sample_page(tasks, total_tasks, per_type)
    replace_file(out, text)
    return out
