"""Reports read stored outcomes; `talkdem verify-run` is the explicit re-execution that lists disagreements."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).parents[1] / "metrics"))
from metrics_helpers import BOOK, LAMP, clean_id, failing, reference, write_run

from talkdem.cli import main
from talkdem.metrics import results_from_run
from talkdem.runs import EPISODES_FILE


def _tamper_plan(run_dir: Path, episode_id: str, plan: list[str]) -> None:
    path = run_dir / EPISODES_FILE
    rows = [json.loads(line) for line in path.read_text().splitlines()]
    for row in rows:
        if row["episode_id"] == episode_id:
            row["plan"] = plan  # the stored outcome and trace are left as they were
    path.write_text("".join(json.dumps(r) + "\n" for r in rows))


def test_reports_read_the_stored_outcome_and_verify_run_lists_the_disagreement(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    run_dir = write_run(tmp_path / "run", {clean_id(BOOK): reference(BOOK), clean_id(LAMP): failing(LAMP)})
    assert main(["verify-run", str(run_dir)]) == 0
    _tamper_plan(run_dir, clean_id(BOOK), ["done"])

    from talkdem.sim.executor import Episode

    def no_execution(*args: object, **kwargs: object) -> None:
        raise AssertionError("building results from a run executed a plan")

    with monkeypatch.context() as patched:
        patched.setattr(Episode, "step", no_execution)
        results = {r.instruction_id: r for r in results_from_run(run_dir)}
    assert results[clean_id(BOOK)].success and not results[clean_id(LAMP)].success
    assert results[clean_id(BOOK)].plan_length == len(reference(BOOK)) - 1  # from the stored trace

    capsys.readouterr()
    assert main(["verify-run", str(run_dir), "--json"]) == 1
    (line,) = capsys.readouterr().out.splitlines()
    row = json.loads(line)
    assert row["episode_id"] == clean_id(BOOK)
    assert row["fields"] == ["success", "goal_conditions", "state_hash"]
    assert row["stored"]["success"] is True and row["replayed"]["success"] is False


def test_a_record_whose_flag_contradicts_its_trace_is_refused(tmp_path: Path) -> None:
    run_dir = write_run(tmp_path / "run", {clean_id(BOOK): reference(BOOK)})
    path = run_dir / EPISODES_FILE
    row = json.loads(path.read_text())
    row["success"] = False
    path.write_text(json.dumps(row) + "\n")
    with pytest.raises(ValueError, match="contradicts the stored trace"):
        results_from_run(run_dir)
