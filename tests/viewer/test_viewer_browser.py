"""The viewer in headless Chromium on the committed runs of the default model under Vanilla and CARE: it opens,
filters, shows an episode with its steps and the highlighted instruction, and takes, keeps and exports a person's
label."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest
from viewer_browser import PAPER, chunk_of, drive, index_of

from talkdem.viewer import ErrorSample, ViewerFiles, word_diff

_LABEL_AND_EXPORT = """
out.ready = document.body.dataset.ready; out.count0 = $('count').textContent; out.chunks0 = chunksLoaded();
out.summary = $('summary').textContent; out.rows0 = rows().length;
set('f-pattern', 'object_substitution'); set('f-outcome', 'retention');
out.filtered = rows(); out.count1 = $('count').textContent; out.chunksAfterFilter = chunksLoaded();
key('j'); key('j'); key('k');
out.selected = document.querySelector('#episodes tr.sel').dataset.row;
key('Enter');
waitFor(opened, function(){
  var cols = document.querySelectorAll('#episode-body .col');
  out.title = $('episode-title').textContent; out.openedRow = Number(document.body.dataset.opened);
  out.steps = Array.from(cols[0].querySelectorAll('.steps tr'))
    .map(function(tr){ return [tr.className, tr.cells[1].textContent, tr.cells[2].textContent]; });
  out.marks = Array.from(cols[0].querySelectorAll('mark.ins')).map(function(m){ return m.textContent; });
  out.instruction = cols[0].querySelector('.instruction').textContent;
  out.goals = Array.from(cols[0].querySelectorAll('ul.goals li')).map(function(li){ return li.textContent; });
  out.cleanHeading = cols[1].querySelector('h3').textContent;
  out.cleanMarks = cols[1].querySelectorAll('mark').length;
  out.reference = Array.from(document.querySelectorAll('#episode-body ol.ref li'))
    .map(function(li){ return li.textContent; });
  out.automatic = ($('automatic') || {}).textContent;
  out.checked = (document.querySelector('#label-box input:checked') || {}).value;
  out.chunksOpen = chunksLoaded();
  key('2');
  out.state = $('label-state').textContent;
  $('export').click();
  out.exported = $('export-text').value;
  key('Escape'); out.paneHidden = $('episode').hidden;
  set('f-label', 'labelled'); out.labelledRows = rows();
  finish();
});
"""

_REVISIT = """
out.tags = Array.from(document.querySelectorAll('.tag.lab')).map(function(t){ return t.textContent; });
set('f-label', 'labelled'); out.labelledRows = rows(); out.progress = $('progress').textContent;
out.exported = window.talkdemViewer.exportLabels();
key('/'); out.focused = document.activeElement.id;
finish();
"""


@pytest.fixture(scope="module")
def session(committed_viewer: ViewerFiles, tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    profile = tmp_path_factory.mktemp("chromium-profile")
    first = drive(committed_viewer.page, _LABEL_AND_EXPORT, profile, name="first-visit")
    again = drive(committed_viewer.page, _REVISIT, profile, name="second-visit")
    return {"first": first, "again": again, "index": index_of(committed_viewer.folder)}


def test_opens_with_every_episode_and_no_detail_loaded(session: dict[str, Any]) -> None:
    seen, index = session["first"], session["index"]
    assert seen["ready"] == "1"
    assert seen["count0"] == "1,920 of 1,920 episodes"
    assert "qwen2.5-coder-0.5b / Vanilla (960)" in seen["summary"]
    assert "qwen2.5-coder-0.5b / CARE (960)" in seen["summary"]
    assert seen["rows0"] == 100  # one page of the table
    assert seen["chunks0"] == [] and seen["chunksAfterFilter"] == []  # details are loaded when an episode opens
    assert len(index["rows"]) == 1920


def test_filters_pattern_and_outcome(session: dict[str, Any]) -> None:
    seen, index = session["first"], session["index"]
    f = {name: i for i, name in enumerate(index["fields"])}
    expected = [
        i
        for i, r in enumerate(index["rows"])
        if r[f["pattern"]] == "object_substitution" and not r[f["success"]] and r[f["clean_solved"]] == 1
    ]
    assert expected, "the committed runs have object-substitution failures of tasks solved clean"
    assert [r["row"] for r in seen["filtered"]] == expected[:100]
    assert seen["count1"] == f"{len(expected)} of 1,920 episodes"
    for row in seen["filtered"]:
        level = index["rows"][row["row"]][f["level"]]
        assert row["cells"][2] == f"Object Substitution L{level}" and row["cells"][4] == "failure"


def test_opened_episode_shows_steps_highlight_clean_twin_and_reference(
    session: dict[str, Any], committed_viewer: ViewerFiles
) -> None:
    seen, index = session["first"], session["index"]
    f = {name: i for i, name in enumerate(index["fields"])}
    second = seen["filtered"][1]
    assert int(seen["selected"]) == second["row"] == seen["openedRow"]  # j, j, k: the second row
    row = index["rows"][second["row"]]
    assert seen["title"] == row[f["episode_id"]]
    chunk, offset = divmod(second["row"], index["chunk_size"])
    detail = chunk_of(committed_viewer.folder, chunk)[offset]
    assert [s[1] for s in seen["steps"]] == [s[0] for s in detail["steps"]] and seen["steps"]
    for (cls, _, result), step in zip(seen["steps"], detail["steps"], strict=True):
        assert (cls == "done") == bool(step[1])
        assert result.startswith("ok") if step[1] else result.startswith("failed") and step[2] in result
    task = index["tasks"][row[f["episode_id"]].split(":")[0]]
    inserted = [text for kind, text in word_diff(task["clean"], row[f["instruction"]]) if kind == "ins"]
    assert seen["marks"] == inserted and inserted
    assert "".join(seen["marks"]) != seen["instruction"]  # shared words are not marked
    assert all(mark in seen["instruction"] for mark in seen["marks"])
    assert seen["cleanHeading"] == "Same task, clean instruction: Clean" and seen["cleanMarks"] == 0
    assert seen["reference"] == task["reference"]
    assert any(g.startswith("✗ missed") for g in seen["goals"])  # a failure misses a goal condition
    assert set(seen["chunksOpen"]) == {second["row"] // 200, row[f["clean_row"]] // 200}


def test_label_is_prefilled_saved_and_exported(session: dict[str, Any], committed_sample: ErrorSample) -> None:
    seen, index = session["first"], session["index"]
    f = {name: i for i, name in enumerate(index["fields"])}
    row = index["rows"][seen["openedRow"]]
    assert seen["checked"] == row[f["error"]] and seen["automatic"].startswith("Automatic error type")
    assert "State Interpretation" in seen["state"]  # key 2: the second type
    exported = json.loads(seen["exported"])
    assert exported["schema"] == "talkdem-error-labels/1"
    assert exported["labels"] == [
        {
            "run": "qwen2.5-coder-0.5b / Vanilla" if row[f["run"]] == 0 else "qwen2.5-coder-0.5b / CARE",
            "run_key": index["runs"][row[f["run"]]]["key"],  # what the report matches the label by
            "episode_id": row[f["episode_id"]],
            "condition": f"object_substitution:{row[f['level']]}",
            "type": "state_interpretation",
            "automatic": row[f["error"]],
        }
    ]
    assert exported["sample"] == {"seed": 7, "per_condition": 3, "n": len(committed_sample.failures)}
    assert seen["downloads"] == [{"name": "talkdem-labels.json", "blob": True}]  # a Blob download of the file
    assert seen["paneHidden"] is True
    assert [r["row"] for r in seen["labelledRows"]] == [seen["openedRow"]]


def test_labels_persist_in_the_browser(session: dict[str, Any]) -> None:
    first, again = session["first"], session["again"]
    assert again["tags"] == ["labelled: State"]
    assert [r["row"] for r in again["labelledRows"]] == [first["openedRow"]]
    assert "1 failure labelled in this browser" in again["progress"]
    assert again["focused"] == "search"  # `/` searches
    assert json.loads(again["exported"])["labels"] == json.loads(first["exported"])["labels"]


def test_every_committed_run_renders(tmp_path: Path) -> None:
    """`talkdem view` over every committed run directory at once (the paper's runs and the clarification runs),
    11,520 episodes."""
    from talkdem.cli import main

    dirs = sorted(p.parent for p in PAPER.parent.rglob("header.json") if ".sweep" not in p.parts)
    assert len(dirs) == 12
    assert main(["view", *map(str, dirs), "--out", str(tmp_path / "all")]) == 0
    index = index_of(tmp_path / "all")
    assert sorted(r["episodes"] for r in index["runs"]) == [960] * 12
    seen = drive(tmp_path / "all" / "index.html", "out.count = $('count').textContent; finish();", tmp_path / "p")
    assert seen["count"] == "11,520 of 11,520 episodes"
