"""The sample page in headless Chromium: it opens without an error, its filters show what they select, the
inserted material is highlighted, and markup in the data stays text."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
from page_browser import drive
from test_sample_page import HOSTILE, _tiny_task
from tiny_dataset import write_tiny_dataset

from talkdem.cli import main
from talkdem.paths import repo_root

_FILTERS = """
function cells(){ return visible('td[data-level]').map(function(td){ return td.dataset.level; }); }
function rows(){ return visible('tr[data-pattern]').map(function(tr){ return tr.dataset.pattern; }); }
function sections(){ return visible('section.task').map(function(s){ return s.dataset.type; }); }
out.ready = document.body.dataset.ready; out.count0 = $('count').textContent;
out.sections0 = sections().length; out.cells0 = cells().length;
out.markedCells = visible('td[data-level]').filter(function(td){ return td.querySelector('mark.ins'); }).length;
out.firstId = document.querySelector('section.task').id;
set('f-pattern', 'intrusion'); out.patternRows = rows(); out.patternCells = cells().length;
set('f-level', '2'); out.levelCells = cells(); out.levelHeads = visible('thead th[data-level]').map(function(th){
  return th.textContent; });
set('f-type', 'pick_heat_then_place_in_recep'); out.typeSections = sections(); out.count1 = $('count').textContent;
set('f-pattern', ''); set('f-level', ''); set('f-type', '');
set('search', out.firstId.toUpperCase()); out.searched = visible('section.task').map(function(s){ return s.id; });
set('search', 'no such words anywhere'); out.count2 = $('count').textContent; out.none = !$('none').hidden;
set('search', ''); out.count3 = $('count').textContent;
"""


@pytest.fixture(scope="module")
def filtered(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    scratch = tmp_path_factory.mktemp("browser")
    page = scratch / "sample.html"
    assert main(["sample-page", str(repo_root() / "data"), "--out", str(page)]) == 0
    return drive(page, _FILTERS, scratch)


def test_opens_with_every_sampled_task_and_no_error(filtered: dict[str, Any]) -> None:
    assert filtered["errors"] == []
    assert filtered["ready"] == "1" and filtered["count0"] == "30 of 30 tasks"
    assert filtered["sections0"] == 30 and filtered["cells0"] == 30 * 15
    # Every pattern adds words to the clean control, so every variant shows highlighted material.
    assert filtered["markedCells"] == 30 * 15


def test_filters_show_what_they_select(filtered: dict[str, Any]) -> None:
    assert filtered["patternRows"] == ["intrusion"] * 30 and filtered["patternCells"] == 30 * 3
    assert filtered["levelCells"] == ["2"] * 30 and filtered["levelHeads"] == ["Level 2"] * 30
    assert filtered["typeSections"] == ["pick_heat_then_place_in_recep"] * 5 and filtered["count1"] == "5 of 30 tasks"
    assert filtered["searched"] == [filtered["firstId"]]  # the search ignores case
    assert filtered["count2"] == "0 of 30 tasks" and filtered["none"] is True
    assert filtered["count3"] == "30 of 30 tasks"


def test_hostile_text_is_shown_as_text(tmp_path: Path) -> None:
    task = _tiny_task(3, "pick_and_place_simple", hostile=True)
    folder = write_tiny_dataset(tmp_path / "data", [task], [task])
    page = tmp_path / "hostile.html"
    assert main(["sample-page", str(folder), "--out", str(page)]) == 0
    steps = """
    out.pwned = window.pwned === undefined ? null : window.pwned;
    out.seed = document.querySelector('dd.seed').textContent;
    out.clean = document.querySelector('dd.clean').textContent;
    out.images = document.images.length; out.scripts = document.scripts.length;
    out.marked = Array.prototype.map.call(document.querySelectorAll('mark.ins'), function(m){ return m.textContent; });
    """
    seen = drive(page, steps, tmp_path)
    assert seen["errors"] == [] and seen["pwned"] is None and seen["images"] == 0
    assert seen["scripts"] == 3  # the page's own and the two the test added
    assert seen["seed"] == f"Put the apple on the shelf. {HOSTILE}"
    assert HOSTILE in seen["clean"]
    assert any("um," in m for m in seen["marked"])
