"""The paper's figures beside ours: extracted from its LaTeX by label, shipped, and added to the report's
tables marked "(paper)", with the paper's own text as an independent check of the extraction."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from builders.paper_figures import PaperTableError, default_paper, extract_tables, main, parse_tabular
from talkdem.metrics import detectable_difference, paired_ttest
from talkdem.metrics import stats as metric_stats
from talkdem.report import ScoredRun, all_tables
from talkdem.report.paper import PAPER_MARK, load_paper_figures, paper_strategy_table

SHIPPED = Path(__file__).parents[2] / "talkdem" / "report" / "paper_reported.json"


def test_the_shipped_figures_are_what_the_builder_extracts_from_the_paper(tmp_path: Path) -> None:
    out = tmp_path / "reported.json"
    assert main(["--paper", str(default_paper()), "--out", str(out)]) == 0
    assert out.read_bytes() == SHIPPED.read_bytes(), "run `python -m builders.paper_figures` and commit the result"


def test_multirow_multicolumn_and_shortstack_cells() -> None:
    body = r"""
\toprule
\textbf{Pattern} & \textbf{Level} & \shortstack{\textbf{Llama-3.1-}\\\textbf{8B}} & \shortstack{a\\b} \\
\midrule
\multicolumn{2}{l}{\textbf{Successful clean tasks ($n$)}} & 200 & 86 \\
\multirow{2}{*}{\shortstack[l]{Referential\\Imprecision}} & L1 & 71.7$^{***}$ & \textbf{89.0} \\
& L2 & -- & 5 \\
Other & L1 & 1 & 2 \\
\bottomrule
"""
    columns, rows = parse_tabular(body, "tab:x")
    assert columns == ("Pattern", "Level", "Llama-3.1-8B", "a b")
    assert rows[0] == ("Successful clean tasks (n)", "", "200", "86")
    assert rows[1] == ("Referential Imprecision", "L1", "71.7***", "89.0")
    assert rows[2] == ("Referential Imprecision", "L2", "–", "5"), "a multirow label carries down"
    assert rows[3][0] == "Other", "and stops after the rows it spans"


def test_a_missing_table_or_a_ragged_row_is_named() -> None:
    with pytest.raises(PaperTableError, match="no \\\\label\\{tab:none\\}"):
        extract_tables("no tables here", ("tab:none",))
    with pytest.raises(PaperTableError, match="tab:x: a row has 3 cells where the header has 2"):
        parse_tabular("a & b \\\\ 1 & 2 & 3 \\\\", "tab:x")


def test_a_bad_paper_is_one_line_and_exit_1(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    bad = tmp_path / "paper.tex"
    bad.write_text("\\label{app:benchmark_results} nothing", encoding="utf-8")
    assert main(["--paper", str(bad), "--out", str(tmp_path / "out.json")]) == 1
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "app:benchmark_results: no tabular after the label" in err
    assert not (tmp_path / "out.json").exists()
    assert main(["--paper", str(tmp_path / "absent.tex"), "--out", str(tmp_path / "out.json")]) == 1
    assert "cannot read the paper" in capsys.readouterr().err


def test_the_extraction_agrees_with_the_papers_own_text() -> None:
    """The paper's prose quotes averages of its tables: recomputing them from the extracted cells checks the
    extraction against figures it did not read."""
    paper = load_paper_figures()
    assert json.loads(SHIPPED.read_text(encoding="utf-8"))["source"]["sha256"] == paper.source_sha256
    means = paper_strategy_table(paper)
    strategies = means.columns[2:]
    assert strategies == ("Vanilla", "AP", "CoT", "ICL", "TOCC", "CARE")
    conditions = means.rows[1:]  # the 15 pattern-level rows
    assert len(conditions) == 15
    # "CARE reached an average success rate of 78.1%, compared with 60.1% for the vanilla prompt, 56.2% for
    # AP, 58.0% for CoT, 64.9% for ICL, and 62.8% for TOCC."
    quoted = {"CARE": 78.1, "Vanilla": 60.1, "AP": 56.2, "CoT": 58.0, "ICL": 64.9, "TOCC": 62.8}
    for index, strategy in enumerate(strategies):
        average = sum(float(row[2 + index]) for row in conditions) / 15
        assert average == pytest.approx(quoted[strategy], abs=0.06), strategy
    # "The mean clean-conditioned retention decreases from 82.1% to 54.4% at Levels 1 to 3" (six open-weight
    # models, Referential Imprecision).
    intensity = paper.table("app:intensity_results")
    for level, quoted_mean in (("L1", 82.1), ("L3", 54.4)):
        row = intensity.row("Referential Imprecision", level)
        assert row is not None
        assert sum(float(v) for v in row[2:8]) / 6 == pytest.approx(quoted_mean, abs=0.06)
    plan = paper.table("tab:plan_length")
    assert plan.row("All") == ("All", "14,721", "8.87", "9.02", "+0.15***")


def test_the_report_sets_the_paper_beside_ours_and_marks_it(mixed_runs: list[ScoredRun]) -> None:
    ours = {t.name: t for t in all_tables(mixed_runs, paper=False)}
    both = {t.name: t for t in all_tables(mixed_runs)}
    for name in ("success", "hazards", "errors", "plan_length", "strategy_retention_by_model"):
        mine, beside = ours[name], both[name]
        assert beside.rows[: len(mine.rows)] == mine.rows, f"{name}: our rows come first, unchanged"
        added = beside.rows[len(mine.rows) :]
        assert added and all(r[0].endswith(PAPER_MARK) for r in added), name
        assert all(len(r) == len(beside.columns) for r in added), name
        assert "(paper)" in beside.caption and "not as results of this package" in beside.caption
    success = both["success"].rows[len(ours["success"].rows) :]
    assert success[0][:4] == ("Llama-3.1-8B-Instruct (paper)", "Vanilla", "4,800", "66.7")
    assert success[0][4] == "-7.9***"
    retention = both["retention"]
    assert retention.columns[: len(ours["retention"].columns)] == ours["retention"].columns
    assert retention.columns[-2:] == ("gemini-3.8 flash (paper)", "claude opus-5 (paper)")
    first = len(ours["retention"].columns)
    assert retention.rows[0][first : first + 2] == ("200", "207")  # successful clean tasks
    assert retention.rows[3][1] == "L3" and retention.rows[3][first] == "46.0"  # RI L3, Llama-3.1-8B
    # Every pattern-level row gets the paper's row of that pattern and level, even where two of our rows are
    # equal (here: identical toy runs), which a lookup by row value would confuse.
    intensity = load_paper_figures().table("app:intensity_results")
    pattern = ""
    for row in retention.rows[1:-1]:
        pattern = row[0] or pattern
        expected = intensity.row(pattern, row[1])
        assert expected is not None and row[first:] == expected[2:], (pattern, row[1])
    assert len({r[:first] for r in retention.rows[1:-1]}) < 15, "the fixture has equal rows of ours"
    # Only strategies our runs compare get the paper's strategy columns; the paper's strategy means follow ours.
    by_model = both["strategy_retention_by_model"]
    assert by_model.columns[1:] == ours["strategy_retention_by_model"].columns[1:]
    names = [t.name for t in all_tables(mixed_runs)]
    assert names[names.index("strategies_paper") - 1].startswith("strategies_"), "right after our strategy tables"


def test_detectable_difference_has_the_power_it_claims() -> None:
    """Simulated: a true mean difference equal to the detectable difference is found at p<0.05 about 80% of
    the time (t approximation at n=60)."""
    rng = np.random.default_rng(7)
    n, sd = 60, 0.3
    sample = rng.normal(0.05, sd, n)
    observed = paired_ttest(list(sample), [0.0] * n)
    effect = detectable_difference(observed)
    assert 0.09 < effect < 0.13  # about 2.86 x 0.3 / sqrt(60) = 0.11, with the sample's own sd
    spread = float(np.std(sample, ddof=1))
    hits = 0
    trials = 2000
    for _ in range(trials):
        draw = rng.normal(effect, spread, n)
        hits += paired_ttest(list(draw), [0.0] * n).p_value < 0.05
    assert 0.76 < hits / trials < 0.84
    assert math.isnan(detectable_difference(metric_stats.TestResult(0.0, math.nan, math.nan, 60)))
    assert math.isnan(detectable_difference(metric_stats.TestResult(0.1, 2.0, 0.05, 1)))
