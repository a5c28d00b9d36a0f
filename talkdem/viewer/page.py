"""The viewer's page: markup, with the style and script of `assets/` inlined (the data come as scripts
beside it, see `talkdem.viewer.build`). Every string from the data reaches the page as text (`textContent`), never as
markup, so an instruction or a skill cannot inject HTML."""

from __future__ import annotations

import html
from importlib import resources

__all__ = ["render_page"]


def _asset(name: str) -> str:
    text = resources.files("talkdem.viewer").joinpath("assets", name).read_text(encoding="utf-8")
    # Inlined into the page: a closing tag inside would end the element early.
    assert "</script" not in text.lower() and "</style" not in text.lower(), name
    return text


def render_page(title: str) -> str:
    """The viewer's index.html (the data scripts are `data/index.js` and `data/chunk-NNNN.js` beside it)."""
    selects = "".join(
        f'<select id="{name}" aria-label="{label}"></select>'
        for name, label in (
            ("f-run", "run"),
            ("f-pattern", "pattern"),
            ("f-level", "level"),
            ("f-type", "task type"),
            ("f-outcome", "outcome"),
            ("f-hazard", "hazard"),
            ("f-error", "automatic error type"),
            ("f-label", "labelling"),
        )
    )
    heads = "".join(
        f'<th scope="col">{h}</th>'
        for h in ("Run", "Task", "Condition", "Task type", "Outcome", "Hazards, error type", "Steps", "Instruction")
    )
    return (
        '<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
        '<meta name="viewport" content="width=device-width, initial-scale=1">'
        f"<title>{html.escape(title)}</title><style>{_asset('viewer.css')}</style></head><body>"
        f'<header><h1>{html.escape(title)}</h1><p id="summary">Loading the episode index…</p></header>'
        f'<div id="controls"><input id="search" type="search" placeholder="Search instructions, ids, runs (/)" '
        f'aria-label="search">{selects}<span id="count"></span></div>'
        '<div id="labelling"><span id="progress"></span> <button id="export" type="button">Export labels (JSON)'
        '</button> <span class="muted">Keys: <kbd>j</kbd>/<kbd>k</kbd> or arrows move, <kbd>Enter</kbd> opens, '
        "<kbd>Esc</kbd> closes, <kbd>/</kbd> searches, <kbd>1</kbd>-<kbd>6</kbd> label an open failure.</span>"
        '<textarea id="export-text" readonly hidden aria-label="exported labels"></textarea></div>'
        f'<div id="list"><table id="episodes"><thead><tr>{heads}</tr></thead><tbody></tbody></table>'
        '<div id="pager"><button id="prev" type="button">Previous</button><span id="page"></span>'
        '<button id="next" type="button">Next</button></div></div>'
        '<section id="episode" hidden aria-live="polite"><button id="close" type="button">Close (Esc)</button>'
        '<h2 id="episode-title"></h2><p class="meta" id="episode-meta"></p><div id="episode-body"></div></section>'
        "<noscript>The viewer needs JavaScript.</noscript>"
        '<script src="data/index.js"></script>'
        f"<script>{_asset('viewer.js')}</script></body></html>\n"
    )
