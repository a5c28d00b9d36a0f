"""A run killed part-way is reported as what it is: its coverage says INCOMPLETE with the counts."""

from __future__ import annotations

from pathlib import Path

from talkdem.report import score_runs, write_report
from talkdem.runs.external import record_plans
from talkdem.runs.sampling import select_episodes
from talkdem.schema import parse_conditions
from talkdem.tasks import get_task


def test_a_partial_run_is_labelled_incomplete(tmp_path: Path) -> None:
    episodes = select_episodes(parse_conditions("clean,intrusion:2"), 2)
    plans = {e.id: get_task(e.task_id).reference_plan for e in episodes}
    run = tmp_path / "partial"
    record_plans(plans, run, "planner-x")
    lines = (run / "episodes.jsonl").read_text().splitlines(keepends=True)
    (run / "episodes.jsonl").write_text("".join(lines[:2]))  # as if killed after two episodes
    (scored,) = score_runs([run], bootstrap=0)
    assert not scored.coverage.complete
    assert "INCOMPLETE: 2 of 4 planned episodes" in scored.coverage.describe()
    files = write_report([scored], tmp_path / "report", plots=False)
    assert "INCOMPLETE: 2 of 4 planned episodes" in files.markdown.read_text()
    record_plans(plans, run, "planner-x")  # resumed to the end
    (resumed,) = score_runs([run], bootstrap=0)
    assert resumed.coverage.complete and "INCOMPLETE" not in resumed.coverage.describe()
