"""The leaderboard folder built from real runs of different coverage: ranking, records, the Space."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

from talkdem.cli import main
from talkdem.leaderboard import RESULTS_SCHEMA, model_dtype, rank_records, read_results, results_record
from talkdem.llm.interface.models import get_model
from talkdem.report import score_runs
from talkdem.schema import PATTERN_CONFIGS


def _records(board: Path) -> list[dict[str, Any]]:
    return json.loads((board / "leaderboard.json").read_text())


def _by_name(board: Path) -> dict[str, dict[str, Any]]:
    return {r["config"]["run_name"]: r for r in _records(board)}


def test_only_runs_over_the_same_episodes_are_ranked_together(board: Path) -> None:
    standings = rank_records(_records(board))
    names = [[r["config"]["run_name"] for _, r in g.ranked] for g in standings.groups]
    # 4-task external runs first (larger coverage), the 1-task planner runs apart; the oracle in neither.
    assert sorted(names[0]) == ["planner A / external", "planner-B / external", "planner_A / external"]
    assert sorted(names[1]) == ["SmolLM2-135M-Instruct.Q4_1.gguf / CARE", "SmolLM2-135M-Instruct.Q4_1.gguf / Vanilla"]
    assert [r["config"]["run_name"] for r in standings.reference] == ["oracle / reference plans"]
    assert standings.groups[0].coverage["tasks"] == 4 and standings.groups[1].coverage["tasks"] == 1


def test_ties_share_a_rank_and_the_next_rank_skips(board: Path) -> None:
    group = rank_records(_records(board)).groups[0]
    ranks = {r["config"]["run_name"]: rank for rank, r in group.ranked}
    assert ranks == {"planner A / external": 1, "planner_A / external": 1, "planner-B / external": 3}
    smol = dict((r["config"]["strategy"], rank) for rank, r in rank_records(_records(board)).groups[1].ranked)
    assert smol == {"care": 1, "vanilla": 2}


def test_records_carry_the_hub_template_fields_and_ours(board: Path) -> None:
    record = _by_name(board)["SmolLM2-135M-Instruct.Q4_1.gguf / CARE"]
    assert record["schema"] == RESULTS_SCHEMA
    config = record["config"]
    assert config["model_name"] == "SmolLM2-135M-Instruct.Q4_1.gguf" == config["model_file"]
    assert config["model_sha"] == "r0" and config["model_dtype"] == "Q4_1"
    assert config["planner"] == "saycan" and config["strategy"] == "care"
    assert {"dataset_hash", "code_revision", "prompt_version", "eval_date"} <= set(config)
    # The template reads results[task][metric] as fractions and skips a task with a null metric.
    results = record["results"]
    assert set(results) == {"talkdem", *(f"talkdem_{p}" for p in PATTERN_CONFIGS)}
    assert results["talkdem"]["clean_sr"] == 1.0
    assert results["talkdem"]["average_sr"] == pytest.approx(1 / 3, abs=1e-4)  # level 1 of 3 solved
    assert all(0 <= v["sr"] <= 1 for k, v in results.items() if k != "talkdem")
    assert record["coverage"]["tasks_per_condition"]["clean"] == 1 and record["coverage"]["of_tasks"] == 300
    low, high = record["intervals"]["average_sr"]
    assert low <= results["talkdem"]["average_sr"] <= high


def test_published_files_hold_no_machine_paths(board: Path, board_runs: dict[str, Path]) -> None:
    for path in board.rglob("*"):
        if path.is_file():
            text = path.read_text(encoding="utf-8")
            assert "/home/someone" not in text, path
            assert str(board_runs["oracle"].parent) not in text, path  # run directories, plan files


def test_runs_whose_names_differ_only_in_punctuation_get_their_own_files(board: Path) -> None:
    files = sorted((board / "results").rglob("*.json"))
    assert len(files) == 6  # one per run, none overwritten
    assert {f.parent.name for f in files} >= {"planner_A", "oracle", "SmolLM2-135M-Instruct.Q4_1.gguf"}
    assert {json.loads(f.read_text())["config"]["run_name"] for f in files} == set(_by_name(board))


def test_the_folder_is_a_static_space(board: Path) -> None:
    from huggingface_hub import SpaceCard

    card = SpaceCard.load(board / "README.md")
    assert card.data.sdk == "static" and card.data.app_file == "index.html"
    assert card.data.colorFrom in {"red", "yellow", "green", "blue", "indigo", "purple", "pink", "gray"}
    assert len(card.data.short_description) <= 60
    assert (board / card.data.app_file).is_file()
    assert "How to submit a run" in card.text and "| 1 | planner A |" in card.text
    page = (board / "index.html").read_text()
    assert "http" not in page and "<link" not in page and "src=" not in page  # no external asset
    assert SpaceCard.load(board / "results" / "README.md").data.pretty_name


def test_a_board_grows_and_can_be_rebuilt_from_its_results(board: Path, tmp_path: Path) -> None:
    rebuilt = tmp_path / "rebuilt"
    assert main(["leaderboard", "--from-results", str(board / "results"), "--out", str(rebuilt)]) == 0
    assert _by_name(rebuilt) == _by_name(board)
    assert (rebuilt / "index.html").read_text() == (board / "index.html").read_text()


def test_model_dtype_and_bad_results_files(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert model_dtype("x/SmolLM2-135M-Instruct.Q4_1.gguf", {}) == "Q4_1"
    assert model_dtype("org/model", {"dtype": "bfloat16"}) == "bfloat16"
    assert model_dtype("org/model", {}) == "unknown"
    default = get_model("default")
    assert default is not None
    assert model_dtype(default.name, {}, default.sha256) == default.quantization == "Q4_K_M"
    assert model_dtype(default.name, {}, "0" * 64) == "unknown"  # another file under the same name: not known
    (tmp_path / "old.json").write_text(json.dumps({"schema": "talkdem-results/1"}))
    with pytest.raises(ValueError, match=r"old\.json: not a talkdem-results/2"):
        read_results(tmp_path)
    assert main(["leaderboard", "--from-results", str(tmp_path), "--out", str(tmp_path / "b")]) == 2
    assert "not a talkdem-results/2 results file" in capsys.readouterr().err
    assert main(["leaderboard", "--out", str(tmp_path / "b")]) == 2


def test_run_ids_tell_apart_runs_with_the_same_label(board_runs: dict[str, Path]) -> None:
    a, twin = score_runs([board_runs["planner A"], board_runs["planner_A"]], bootstrap=0)
    assert results_record(a)["run_id"] != results_record(twin)["run_id"]
    assert (
        results_record(a)["run_id"] == results_record(score_runs([board_runs["planner A"]], bootstrap=0)[0])["run_id"]
    )


def test_the_committed_runs_keep_their_published_ids() -> None:
    # A run's id names its results file on the Hub: a newer version reading the same run (a header written before
    # a field existed) must give the id that was published, or the same run would be listed twice.
    from talkdem.leaderboard.records import run_id
    from talkdem.paths import repo_root

    paper = repo_root() / "results" / "paper"
    published = {p.stem.rsplit("_", 1)[-1] for p in (paper / "leaderboard" / "results").rglob("results_*.json")}
    runs = sorted(p for p in paper.glob("qwen2.5-coder-0.5b-*") if (p / "header.json").is_file())
    assert len(runs) == 6
    for run in score_runs(runs, bootstrap=0):
        assert "runtimes" not in json.loads((run.run_dir / "header.json").read_text())
        assert run_id(run) in published, run.run_dir.name


def test_a_run_that_recorded_its_runtimes_publishes_them(board_runs: dict[str, Path], tmp_path: Path) -> None:
    # The same model and code can score differently on another CPU build; the results file says where each
    # sitting ran, and a run recorded before runtimes existed publishes the same record as before.
    import shutil

    from talkdem.leaderboard import validate_record

    before = results_record(score_runs([board_runs["smol care"]], bootstrap=0)[0])
    assert "runtimes" not in before
    run = tmp_path / "smol-care"
    shutil.copytree(board_runs["smol care"], run)
    header = json.loads((run / "header.json").read_text())
    sittings = [
        {"python": "3.11.9", "platform": "Linux x86_64", "cpu": "CPU one", "llama_cpp_python": "0.3.36"},
        {"python": "3.11.9", "platform": "Linux x86_64", "cpu": "CPU two", "llama_cpp_python": "0.3.36"},
    ]
    (run / "header.json").write_text(json.dumps({**header, "runtimes": sittings}))
    record = results_record(score_runs([run], bootstrap=0)[0])
    assert record["runtimes"] == sittings
    assert record["run_id"] != before["run_id"]  # a recorded runtime is part of what the run is
    assert {k: v for k, v in record.items() if k not in ("runtimes", "run_id")} == {
        k: v for k, v in before.items() if k != "run_id"
    }
    validate_record(record, "r.json")
