"""`talkdem report` and `talkdem leaderboard` on small run directories of real executed plans."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from metrics_helpers import BOOK, COOL, HEAT, LAMP, clean_id, failing, pattern_id, reference, write_run

from talkdem.cli import main
from talkdem.report import all_tables, score_runs, strategy_retention_table
from talkdem.schema import PATTERN_CONFIGS

TASKS = (BOOK, LAMP, HEAT, COOL)


def plans(solve_level_3: bool) -> dict[str, list[str]]:
    out = {clean_id(t): reference(t) for t in TASKS}
    for task in TASKS:
        for pattern in PATTERN_CONFIGS:
            for level in (1, 2, 3):
                ok = level < 3 or solve_level_3 or task == BOOK
                out[pattern_id(task, pattern, level)] = reference(task) if ok else failing(task)
    return out


@pytest.fixture(scope="module")
def run_dirs(tmp_path_factory: pytest.TempPathFactory) -> list[Path]:
    root = tmp_path_factory.mktemp("runs")
    return [
        write_run(root / "vanilla", plans(False), strategy="vanilla"),
        write_run(root / "care", plans(True), strategy="care"),
    ]


def test_tables_have_the_paper_layouts(run_dirs: list[Path]) -> None:
    runs = score_runs(run_dirs, bootstrap=0)
    tables = {t.name: t for t in all_tables(runs, paper=False)}
    success = tables["success"]
    assert success.columns == ("Model", "Strategy", "n", "Clean", "RI", "OS", "ES", "TD", "IN", "Detectable")
    # vanilla: level 3 fails for 3 of 4 tasks -> pattern SR (1 + 1 + 1/4)/3 = 75%, change -25.0 points
    assert success.rows[0][:4] == ("tiny-model", "Vanilla", "64", "100.0")
    assert success.rows[0][4].startswith("-25.0")
    assert success.rows[1][4] == "+0.0"
    retention = tables["retention"]
    assert retention.rows[0] == ("Successful clean tasks (n)", "", "4", "4")
    assert retention.rows[3] == ("", "L3", "25.0", "100.0")
    assert tables["strategy_retention_by_model"].rows[0][1:] == ("75.0", "**100.0**")
    # Bold is the row's best, not the reference: against Vanilla as reference, CARE's higher retention stays bold
    # (4 tasks are too few for a significant difference: no star, no dagger)
    against_vanilla = strategy_retention_table(runs, "Vanilla")
    assert against_vanilla is not None and against_vanilla.rows[0][1:] == ("75.0", "**100.0**")
    per_strategy = tables["strategies_1"]
    assert per_strategy.rows[0][2:] == ("100.00", "100.00"), "a tie has no best: nothing bold"
    assert per_strategy.rows[3][2:] == ("25.00", "**100.00**")  # Referential Imprecision L3
    # CARE - Vanilla per task over all 16 conditions: 0 for BOOK, 5/16 for the other three -> +23.4 points;
    # 4 tasks are too few for significance (paired t = 3.0, p ~ 0.058): no star
    (tested,) = tables["strategy_success_test"].rows
    assert tested[:5] == ("tiny-model", "Vanilla", "CARE", "4", "16")
    assert tested[5:8] == ("76.6", "100.0", "-23.4")
    assert 0.05 < float(tested[8]) < 0.07
    assert tables["errors"].rows[-1][-1] == str(3 * 5)  # 3 failed level-3 episodes per pattern, all typed
    assert tables["plan_length"].columns == ("Pattern", "n", "Clean", "Transformed", "Δ")
    assert tables["hazards"].rows[-2][0] == "Distinct cases"


def test_a_second_model_is_compared_under_the_same_strategy_and_never_pooled_unevenly(
    run_dirs: list[Path], tmp_path: Path
) -> None:
    bigger = write_run(tmp_path / "bigger", plans(True), model="bigger-model", strategy="vanilla")
    runs = score_runs([*run_dirs, bigger], bootstrap=0)
    tables = {t.name: t for t in all_tables(runs, paper=False)}
    # bigger-model solves everything; tiny-model under Vanilla fails level 3 of every pattern on 3 of 4 tasks:
    # per task 16/16 (BOOK) or 11/16 -> 76.6%; RI per task over its levels: 0 or 1/3 of the way -> +25.0 points.
    (row,) = tables["model_comparison"].rows
    assert row[:7] == ("Vanilla", "bigger-model", "tiny-model", "4", "100.0", "76.6", "+23.4")
    assert 0.05 < float(row[7]) < 0.07  # 4 tasks: paired t = 3.0
    assert row[8] == "+0.0" and row[9] == "+25.0"  # clean: no difference; RI: no star
    # Only tiny-model ran both strategies: no Average row, and the rows by pattern are tiny-model's alone (pooling
    # bigger-model's Vanilla would raise Vanilla's RI retention from 75.0 to 87.5 beside a one-model CARE).
    by_model = tables["strategy_retention_by_model"]
    assert [r[0] for r in by_model.rows] == ["tiny-model", "bigger-model"]
    assert by_model.rows[1][1:] == ("100.0", "–")
    by_pattern = tables["strategy_retention_by_pattern"]
    assert by_pattern.rows[0][1:] == ("75.0", "**100.0**")
    assert "pool tiny-model (not bigger-model: not run under every strategy)" in by_pattern.caption


def test_oracle_and_external_plans_are_scored_but_not_compared_as_strategies(
    run_dirs: list[Path], tmp_path: Path
) -> None:
    from talkdem.instructions import load_instructions
    from talkdem.runs.oracle import write_oracle_run

    episodes = [i for i in load_instructions() if i.task_id in TASKS]
    oracle = tmp_path / "oracle"
    write_oracle_run(episodes, oracle)
    runs = score_runs([*run_dirs, oracle], bootstrap=0)
    tables = {t.name: t for t in all_tables(runs, paper=False)}
    assert tables["success"].rows[-1][:4] == ("oracle", "reference plans", "64", "100.0")
    assert tables["strategy_retention_by_model"].columns[1:] == ("Vanilla", "CARE")
    assert all("reference plans" not in t.columns for t in tables.values() if t.name.startswith("strateg"))


def test_cli_report_writes_tables_scores_and_plots(run_dirs: list[Path], tmp_path: Path, capsys) -> None:  # type: ignore[no-untyped-def]
    out = tmp_path / "report"
    assert main(["report", *map(str, run_dirs), "--out", str(out), "--bootstrap", "50"]) == 0
    printed = capsys.readouterr().out
    assert "| tiny-model | Vanilla | 64 | 100.0 |" in printed
    for name in ("success", "retention", "hazards", "errors", "plan_length"):
        for suffix in (".md", ".csv", ".json"):
            assert (out / "tables" / f"{name}{suffix}").is_file()
    for plot in ("success_by_pattern.png", "retention_by_level.png", "strategy_radar.png"):
        assert (out / "plots" / plot).stat().st_size > 1000
    scores = json.loads((out / "scores" / "tiny-model_Vanilla.json").read_text())
    assert scores["retention"]["average"] == pytest.approx(2 / 3 * 1 + 1 / 3 * 0.25)


def test_cli_leaderboard_writes_results_and_a_static_page(run_dirs: list[Path], tmp_path: Path) -> None:
    out = tmp_path / "board"
    assert main(["leaderboard", *map(str, run_dirs), "--out", str(out), "--bootstrap", "0"]) == 0
    (path,) = [
        p for p in (out / "results").rglob("*.json") if json.loads(p.read_text())["config"]["strategy"] == "care"
    ]
    record = json.loads(path.read_text())
    assert record["schema"] == "talkdem-results/2" and path.parent.name == "tiny-model"
    assert record["config"]["model_name"] == "tiny-model" and record["config"]["model_sha"] == "r0"
    assert record["results"]["talkdem"]["average_sr"] == 1.0
    assert set(record["results"]) == {"talkdem", *(f"talkdem_{p}" for p in PATTERN_CONFIGS)}
    page = (out / "index.html").read_text()
    assert page.index("CARE") < page.index("Vanilla")  # ranked by average SR
    assert "http" not in page and "<link" not in page and "src=" not in page  # no external assets


def test_report_on_a_missing_run_directory_fails_cleanly(tmp_path: Path, capsys) -> None:  # type: ignore[no-untyped-def]
    assert main(["report", str(tmp_path / "absent")]) == 2
    assert "not a run directory" in capsys.readouterr().err


def test_retention_marks_name_the_direction_of_a_significant_difference() -> None:
    from talkdem.metrics.stats import TestResult
    from talkdem.report.tables import _marked

    assert _marked(TestResult(-0.2, -4.0, 0.004, 30)) == "**", "reference higher: the paper's stars"
    assert _marked(TestResult(0.2, 4.0, 0.004, 30)) == "†", "the strategy higher than the reference: a dagger"
    assert _marked(TestResult(0.2, 1.0, 0.3, 30)) == ""
    assert _marked(None) == ""


def test_the_run_list_says_where_each_run_computed_its_numbers(run_dirs: list[Path], tmp_path: Path) -> None:
    import shutil

    from talkdem.runs.runtime import describe_runtimes

    sittings = (
        {"python": "3.11.9", "platform": "Linux x86_64", "cpu": "CPU one", "llama_cpp_python": "0.3.36",
         "llama_cpp_system_info": "CPU : AVX2 = 1 |"},
        {"python": "3.11.9", "platform": "Linux aarch64", "cpu": "", "torch": "2.5.1", "device": "cpu"},
    )  # fmt: skip
    assert describe_runtimes(sittings) == "CPU one, llama-cpp-python 0.3.36; Linux aarch64, torch 2.5.1, device cpu"
    assert describe_runtimes(()) == ""
    recorded = tmp_path / "care"
    shutil.copytree(run_dirs[1], recorded)
    header = json.loads((recorded / "header.json").read_text())
    (recorded / "header.json").write_text(json.dumps({**header, "runtimes": [sittings[0]]}))
    out = tmp_path / "report"
    assert main(["report", str(run_dirs[0]), str(recorded), "--out", str(out), "--no-plots"]) == 0
    listed = [line for line in (out / "report.md").read_text().splitlines() if line.startswith("- tiny-model")]
    assert listed[0].endswith("16/16 conditions")  # no runtime recorded: none claimed
    assert listed[1].endswith(", computed on CPU one, llama-cpp-python 0.3.36")
    assert "<td>CPU one, llama-cpp-python 0.3.36</td>" in (out / "report.html").read_text()
