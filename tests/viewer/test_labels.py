"""The error sample (seeded, the paper's population), labels files checked strictly, Cohen's kappa, and
`talkdem report --labels` with the taxonomy table and the agreement; the report and leaderboard link the viewer."""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path
from typing import Any

import pytest
from viewer_browser import COMMITTED

from talkdem.cli import main
from talkdem.metrics import ErrorType
from talkdem.report import ScoredRun, score_runs
from talkdem.viewer import ErrorSample, ViewedRun, cohen_kappa, label_tables, read_labels, sample_errors


def test_sample_is_the_papers_population_seeded_and_capped(
    committed_runs: list[ViewedRun], committed_sample: ErrorSample
) -> None:
    candidates: dict[tuple[str, str], set[str]] = {}
    for run in committed_runs:
        for e in run.episodes:
            if e.is_pattern and not e.success and e.clean_solved:
                candidates.setdefault((run.label, str(e.record.condition)), set()).add(e.episode_id)
    drawn: dict[tuple[str, str], list[str]] = {}
    for failure in committed_sample.failures:
        drawn.setdefault((failure.run, failure.condition), []).append(failure.episode_id)
    assert set(drawn) == set(candidates)  # every run and condition with a candidate is drawn from
    for group, ids in drawn.items():
        assert len(ids) == min(3, len(candidates[group])) == len(set(ids))
        assert set(ids) <= candidates[group]
    covered = {(r.label, str(e.record.condition)) for r in committed_runs for e in r.episodes if e.is_pattern}
    assert {(r, c) for r, c, _ in committed_sample.short} == {g for g in covered if len(candidates.get(g, ())) < 3}
    again = sample_errors(committed_runs, 3, seed=7)
    assert again == committed_sample
    assert sample_errors(committed_runs, 3, seed=8).failures != committed_sample.failures
    shuffled = [dataclasses.replace(r, episodes=tuple(reversed(r.episodes))) for r in committed_runs]
    assert sample_errors(shuffled, 3, seed=7).failures == committed_sample.failures  # stored order does not matter
    assert len(sample_errors(committed_runs, 1, seed=7).failures) == len(drawn)


def test_cohen_kappa_on_a_worked_example() -> None:
    # 50 items, two raters: 20 both A, 15 both B, 5 A/B, 10 B/A -> p_o = 0.7, p_e = 0.5, kappa = 0.4
    a, b = ErrorType.REFERENT, ErrorType.SUBGOAL
    pairs = [(a, a)] * 20 + [(b, b)] * 15 + [(a, b)] * 5 + [(b, a)] * 10
    assert cohen_kappa(pairs) == pytest.approx(0.4)
    assert cohen_kappa([(a, a), (b, b)]) == pytest.approx(1.0)
    assert math.isnan(cohen_kappa([(a, a), (a, a)])) and math.isnan(cohen_kappa([]))


@pytest.fixture(scope="module")
def scored() -> list[ScoredRun]:
    return score_runs(list(COMMITTED), bootstrap=0)


def _labels_file(path: Path, sample: ErrorSample, change: dict[int, dict[str, Any]] | None = None) -> Path:
    labels = [
        {"run": f.run, "episode_id": f.episode_id, "type": f.automatic.value, "automatic": f.automatic.value}
        for f in sample.failures
    ]
    for n, fields in (change or {}).items():
        labels[n].update(fields)
    path.write_text(json.dumps({"schema": "talkdem-error-labels/1", "labels": labels}), encoding="utf-8")
    return path


def test_labels_against_the_classifier(scored: list[ScoredRun], committed_sample: ErrorSample, tmp_path: Path) -> None:
    first = committed_sample.failures[0]
    other = next(t for t in ErrorType if t != first.automatic)
    labels = read_labels(_labels_file(tmp_path / "l.json", committed_sample, {0: {"type": other.value}}), scored)
    assert len(labels) == len(committed_sample.failures)
    assert [label.automatic for label in labels] == [f.automatic for f in committed_sample.failures]
    human, summary, matrix = label_tables(labels, "l.json")
    n = len(labels)
    assert human.rows[-1][-1] == str(n) and summary.rows[0][0] == str(n)
    assert summary.rows[0][1] == f"{100 * (n - 1) / n:.1f}"
    pairs = [(label.human, label.automatic) for label in labels]
    assert summary.rows[0][2] == f"{cohen_kappa(pairs):.2f}" and float(summary.rows[0][2]) < 1
    types = list(ErrorType)
    assert matrix.rows[types.index(other)][1 + types.index(first.automatic)] == "1"  # the one disagreement
    assert sum(int(matrix.rows[i][1 + i]) for i in range(6)) == n - 1


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"type": "referent"}, "unknown type 'referent' (expected one of referent_resolution, "),
        ({"episode_id": "trial_nope:intrusion:3"}, "unknown episode id (not among the 960 episodes of "),
        ({"run": "someone else / CARE"}, "unknown run 'someone else / CARE' (the runs reported: "),
        ({"episode_id": None}, "'run', 'episode_id' and 'type' must be strings"),
    ],
)
def test_bad_labels_are_one_line_naming_the_file_and_entry(
    scored: list[ScoredRun], committed_sample: ErrorSample, tmp_path: Path, change: dict[str, Any], message: str
) -> None:
    path = _labels_file(tmp_path / "labels.json", committed_sample, {4: change})
    with pytest.raises(ValueError) as caught:
        read_labels(path, scored)
    text = str(caught.value)
    assert text.startswith(f"{path}: label 5") and message in text and "\n" not in text


def test_labels_of_successes_clean_episodes_and_duplicates_are_refused(
    scored: list[ScoredRun], committed_sample: ErrorSample, tmp_path: Path
) -> None:
    vanilla = scored[0]
    solved = next(e for e in vanilla.scores.episodes if e.success and not e.condition.is_clean)
    clean = next(e for e in vanilla.scores.episodes if e.condition.is_clean and not e.success)
    cases = [
        ({"run": vanilla.label, "episode_id": solved.instruction_id}, "an episode that succeeded"),
        ({"run": vanilla.label, "episode_id": clean.instruction_id}, "a clean episode"),
        (
            {"run": committed_sample.failures[0].run, "episode_id": committed_sample.failures[0].episode_id},
            "a second label for this episode (the first is label 1)",
        ),
    ]
    for change, message in cases:
        with pytest.raises(ValueError, match=r"label 2 \(.*\): " + message.replace("(", r"\(").replace(")", r"\)")):
            read_labels(_labels_file(tmp_path / "x.json", committed_sample, {1: change}), scored)
    for text, message in (("{", "not JSON"), ('{"labels": []}', "not a labels file"), ("[]", "not a labels file")):
        (tmp_path / "y.json").write_text(text)
        with pytest.raises(ValueError, match=message):
            read_labels(tmp_path / "y.json", scored)


def test_report_with_labels_and_viewer_link(
    committed_sample: ErrorSample, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    labels = _labels_file(tmp_path / "my-labels.json", committed_sample)
    out = tmp_path / "report"
    args = ["report", *map(str, COMMITTED), "--labels", str(labels), "--viewer", "../viewer/index.html"]
    assert main([*args, "--no-plots", "--bootstrap", "0", "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "### Error types across communication patterns (human labels)" in printed
    n = len(committed_sample.failures)
    assert f"| {n} | 100.0 | 1.00 |" in printed  # labels equal to the classifier's: full agreement
    page = (out / "report.html").read_text(encoding="utf-8")
    assert 'id="table-errors_human"' in page and 'id="table-errors_confusion"' in page
    assert '<a href="../viewer/index.html">Browse every episode</a>' in page
    assert "[the viewer](../viewer/index.html)" in (out / "report.md").read_text(encoding="utf-8")
    assert str(tmp_path) not in page  # the labels file is named, not its path
    assert main(["report", str(COMMITTED[0]), "--labels", str(labels), "--no-plots", "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "unknown run 'qwen2.5-coder-0.5b / CARE'" in err and str(labels) in err
    with pytest.raises(SystemExit) as refused:  # argparse refuses it before any work
        main(["report", str(COMMITTED[0]), "--viewer", "/home/me/viewer", "--out", str(out)])
    assert refused.value.code == 2 and "not a relative or http(s) link" in capsys.readouterr().err


def test_leaderboard_links_the_viewer(tmp_path: Path) -> None:
    from talkdem.leaderboard import render_html

    assert "viewer-link" not in render_html([])
    page = render_html([], viewer='viewer/index.html?a="b"')
    assert '<a href="viewer/index.html?a=&quot;b&quot;">Browse every episode</a>' in page
