"""The report's clarification section: present only for runs that asked, paired with the run without."""

from __future__ import annotations

from pathlib import Path

import pytest
from test_clarify_run import ARGS

from talkdem.cli import main
from talkdem.report import score_runs
from talkdem.report.tables import all_tables


@pytest.fixture(scope="module")
def runs(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    root = tmp_path_factory.mktemp("clarify-report")
    out = {"none": root / "none", "oracle": root / "oracle"}
    conditions = ["--conditions", "clean,intrusion:1"]
    assert main([*ARGS, *conditions, "--out", str(out["none"])]) == 0
    assert main([*ARGS, *conditions, "--clarify", "oracle", "--out", str(out["oracle"])]) == 0
    return out


def test_a_report_without_clarification_has_no_such_section(runs: dict[str, Path]) -> None:
    tables = all_tables(score_runs([runs["none"]], bootstrap=0))
    assert "clarification" not in [t.name for t in tables]


def test_the_clarification_table_pairs_the_run_without(runs: dict[str, Path]) -> None:
    scored = score_runs([runs["none"], runs["oracle"]], bootstrap=0)
    assert scored[1].label.endswith("+ ask (oracle)")
    table = next(t for t in all_tables(scored) if t.name == "clarification")
    groups = [row[2] for row in table.rows]
    assert groups == ["all", "clean", "IN", "IN L1"]
    by_group = {row[2]: row for row in table.rows}
    assert all(row[0] == scored[1].label and row[1] == "oracle" for row in table.rows)
    assert by_group["all"][3] == "4"
    assert by_group["all"][6] == "2.00"  # the test model asks both of its questions in every episode
    assert by_group["all"][5] != "–"  # paired with the run without clarification
    assert by_group["clean"][12] == "4"  # two questions on each of the two clean instructions
    assert by_group["all"][11] == "+0/−0", "every episode asked: no flip can be without a question"
    assert by_group["all"][10].startswith("+")


def test_a_clarification_run_is_never_read_as_its_strategy(runs: dict[str, Path]) -> None:
    scored = score_runs([runs["none"], runs["oracle"]], bootstrap=0)
    tables = {t.name: t for t in all_tables(scored, paper=False)}
    assert [row[1] for row in tables["success"].rows] == [scored[0].strategy, f"{scored[0].strategy} + ask (oracle)"]
    # the same strategy with and without questions is not a strategy comparison (the clarification table is)
    assert not [name for name in tables if name.startswith("strateg")]


def test_leaderboard_records_and_page_carry_clarification_only_when_present(runs: dict[str, Path]) -> None:
    from talkdem.leaderboard.page import render_html
    from talkdem.leaderboard.records import results_record
    from talkdem.leaderboard.validate import ResultsFileError, validate_record

    scored = score_runs([runs["none"], runs["oracle"]], bootstrap=0)
    plain, asked = (results_record(run) for run in scored)
    assert "talkdem_clarification" not in plain["results"]
    block = asked["results"]["talkdem_clarification"]
    assert (asked["config"]["clarify"], block["questions_per_episode"], block["help_rate"]) == ("oracle", 2.0, 1.0)
    assert "clarify" not in plain["config"]
    assert block["unneeded_questions"] == 4
    assert validate_record(asked, "asked.json") is asked
    assert ">Asks<" not in render_html([plain])
    page = render_html([plain, asked])
    assert ">Asks<" in page and ">oracle<" in page
    broken = {**asked, "config": {**asked["config"], "clarify": "maybe"}}
    with pytest.raises(ResultsFileError, match=r"config\.clarify"):
        validate_record(broken, "broken.json")
