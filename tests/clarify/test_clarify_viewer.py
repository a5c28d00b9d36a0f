"""The viewer shows a clarification episode's questions and answers where they were asked, between the
steps, in headless Chromium; a run without clarification shows none."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

import pytest

TESTS = Path(__file__).parent.parent
sys.path.insert(0, str(TESTS / "leaderboard"))
sys.path.insert(0, str(TESTS / "viewer"))

from test_clarify_run import ARGS, CONDITIONS  # noqa: E402
from viewer_browser import drive  # noqa: E402

from talkdem.cli import main  # noqa: E402
from talkdem.runs import read_episodes  # noqa: E402
from talkdem.viewer import load_runs, write_viewer  # noqa: E402

_OPEN_FIRST = """
key('Enter');
waitFor(opened, function(){
  var col = document.querySelector('#episode-body .col');
  out.heading = Array.from(col.querySelectorAll('h3')).map(function(h){ return h.textContent; });
  out.rows = Array.from(col.querySelectorAll('.steps tr')).map(function(tr){
    return [tr.className, tr.cells[0].textContent, tr.cells[1].textContent, tr.cells[2].textContent]; });
  finish();
});
"""


@pytest.fixture(scope="module")
def pages(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    root = tmp_path_factory.mktemp("clarify-viewer")
    seen: dict[str, Any] = {}
    for mode in ("oracle", "none"):
        run = root / mode
        clarify = ["--clarify", mode] if mode != "none" else []
        assert main([*ARGS, *CONDITIONS, *clarify, "--out", str(run)]) == 0
        files = write_viewer(load_runs([run]), root / f"viewer-{mode}")
        seen[mode] = drive(files.page, _OPEN_FIRST, root / f"profile-{mode}")
        seen[f"{mode}-record"] = read_episodes(run)[0]
    return seen


def test_questions_and_answers_sit_between_the_steps(pages: dict[str, Any]) -> None:
    record = pages["oracle-record"]
    dialogue = record.trace["dialogue"]
    assert len(dialogue) == 2  # the test model asks both of its questions first
    rows = pages["oracle"]["rows"]
    asked = [r for r in rows if r[0] == "ask"]
    assert [r[2] for r in asked] == [f"Robot: {x['question']}Person: {x['answer']}" for x in dialogue]
    assert [r[3] for r in asked] == [x["slot"].replace("_", " ") for x in dialogue]
    # asked before any action, so before the first step; the steps follow in order
    assert [r[0] for r in rows[:2]] == ["ask", "ask"] and rows[2][1] == "0"
    assert [r[2] for r in rows if r[0] != "ask"] == list(record.plan)
    assert "Plan and simulator feedback (2 questions asked)" in pages["oracle"]["heading"]


def test_a_run_without_clarification_shows_no_dialogue(pages: dict[str, Any]) -> None:
    rows = pages["none"]["rows"]
    assert rows and all(r[0] != "ask" for r in rows)
    assert "Plan and simulator feedback" in pages["none"]["heading"]
