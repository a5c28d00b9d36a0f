"""Replaying a dataset's ranking choices: the shipped data is what the builder writes, without hours of ranking;
a row the generator no longer draws shows up; the ranking model still gives the shipped scores; another margin
chooses again from the recorded scores."""

from __future__ import annotations

import json
import math
import shutil
from pathlib import Path

import pyarrow as pa
import pyarrow.parquet as pq
import pytest

from builders.build import BuildResult, build, dataset_files
from builders.generation.ranking import RecordedRanker
from builders.replay import recorded_rows, replay
from talkdem.paths import repo_root

DATA = repo_root() / "data"
RANK_MODEL = "qwen2.5-coder-0.5b"
MACHINE_NOISE = 0.05
"""Nats per token by which one candidate's mean score may move between machines. llama.cpp's quantised
kernels differ by CPU (its wheel is built on the machine that installs it): data/ was ranked on one machine,
and on the 2-core AMD EPYC (AVX2) machines CI runs on, the 122 verified candidates of the first benchmark and
memory tasks score up to 0.026 nats per token apart from it (mean 0.008)."""


@pytest.fixture(scope="module")
def ranked(tmp_path_factory: pytest.TempPathFactory) -> BuildResult:
    """The first benchmark task and the first memory task, ranked by the default planner model (as data/ is)."""
    root = tmp_path_factory.mktemp("ranked")
    return build(root / "data", checkpoint=root / "c.jsonl", progress=False, limit=1, rank_model=RANK_MODEL)


def test_recorded_ranker_scores_the_recorded_candidates_and_nothing_else() -> None:
    scored = [{"seed": 11, "score": -2.5}, {"seed": 12, "score": -2.25}]
    rows = [
        {"instruction": "Put the mug away.", "seed": 11, "ranking": {"model": "m@1", "score": -2.5, "scored": scored}},
        {"instruction": "Er, the mug.", "seed": 3, "ranking": {"model": None, "score": None, "scored": []}},
    ]
    ranker = RecordedRanker.from_rows(rows, margin=0.5)
    assert ranker is not None and ranker.model_id == "m@1" and ranker.margin == 0.5
    assert ranker.score_candidates([(12, "other"), (3, "Er, the mug."), (11, "x")]) == [-2.25, -math.inf, -2.5]
    assert RecordedRanker.from_rows(rows[1:]) is None
    with pytest.raises(ValueError, match="more than one model"):
        RecordedRanker.from_rows([*rows, {"instruction": "x", "seed": 5, "ranking": {"model": "n@2", "score": -1.0}}])
    with pytest.raises(ValueError, match="margin"):
        RecordedRanker.from_rows(rows, margin=-1.0)


def test_a_ranked_build_replays_to_the_same_bytes(ranked: BuildResult, tmp_path: Path) -> None:
    stats = replay(ranked.folder, tmp_path / "replayed")
    assert stats["build"]["rank_model"].startswith(f"llamacpp:{RANK_MODEL}@")
    assert dataset_files(tmp_path / "replayed") == dataset_files(ranked.folder)
    # the rows read back are the build's own (class labels by name, nulls kept), ready to build from
    from builders.build import build_unit
    from talkdem.speech import get_generator
    from talkdem.tasks import load_tasks

    task = load_tasks("benchmark")[0]
    rows = recorded_rows(ranked.folder)[f"benchmark:{task.task_id}"]
    assert [r["pattern"] for r in rows[:2]] == ["clean", "referential_imprecision"]
    assert build_unit(get_generator("rules"), task, 0, ranker=RecordedRanker.from_rows(rows)) == rows


def test_a_row_the_generator_does_not_draw_does_not_replay(ranked: BuildResult, tmp_path: Path) -> None:
    edited = tmp_path / "edited"
    shutil.copytree(ranked.folder, edited)
    path = edited / "topic_drift" / "level_3.parquet"
    table = pq.read_table(path)
    rows = table.to_pylist()
    rows[0]["instruction"] += " Anyway."  # not a candidate of its request any more
    pq.write_table(pa.Table.from_pylist(rows, schema=table.schema), path)
    replay(edited, tmp_path / "replayed")
    replayed = dataset_files(tmp_path / "replayed")
    different = [name for name, data in dataset_files(edited).items() if replayed[name] != data]
    assert different == ["topic_drift/level_3.parquet"]


def test_another_margin_chooses_again_from_the_recorded_scores(ranked: BuildResult, tmp_path: Path) -> None:
    # a margin wider than any spread keeps the first verified candidate: what the unranked build keeps
    stats = replay(ranked.folder, tmp_path / "wide", margin=1000.0)
    assert stats["build"]["rank_margin"] == 1000.0
    plain = build(tmp_path / "plain", checkpoint=tmp_path / "c.jsonl", progress=False, limit=1)
    wide, first = recorded_rows(tmp_path / "wide"), recorded_rows(plain.folder)
    assert sorted(wide) == sorted(first)
    for key in wide:
        assert [r["instruction"] for r in wide[key]] == [r["instruction"] for r in first[key]]
    changed = [
        r for key, rows in recorded_rows(ranked.folder).items() for r, w in zip(rows, wide[key], strict=True)
        if r["seed"] != w["seed"]
    ]  # fmt: skip
    assert changed, "on two tasks the best-scored candidate is some request's first draw every time"
    with pytest.raises(ValueError, match="no scores to choose from"):
        replay(plain.folder, tmp_path / "again", margin=0.1)


def test_shipped_data_is_what_the_build_writes(tmp_path: Path) -> None:
    from builders.card import render_card

    replay(DATA, tmp_path / "data")
    built = dataset_files(tmp_path / "data")
    shipped = dataset_files(DATA)
    assert sorted(built) == sorted(shipped)
    # the card also shows what `talkdem markers` and `talkdem validate-dataset` wrote beside it in data/
    card = render_card(json.loads(shipped.pop("build_stats.json")), DATA)
    assert shipped.pop("README.md").decode() == card
    built.pop("README.md")
    assert built.pop("build_stats.json") == (DATA / "build_stats.json").read_bytes()
    stale = [name for name in built if built[name] != shipped[name]]
    assert not stale, f"data/ is out of date with the builder (run `talkdem build`, see the card): {stale}"


def test_the_ranking_model_scores_the_shipped_candidates_alike(ranked: BuildResult) -> None:
    """The replay checks the choice rule on the recorded scores; this checks the model: run here, it scores the
    same verified candidates of the first benchmark and memory tasks as data/ records, within MACHINE_NOISE, and
    chooses what data/ chose wherever the recorded scores decide the choice by more than that noise can move."""
    from builders.generation.ranking import choose

    margin = json.loads((DATA / "build_stats.json").read_text())["build"]["rank_margin"] or 0.0
    shipped_rows, fresh_rows = recorded_rows(DATA), recorded_rows(ranked.folder)
    units = [key for key in fresh_rows if key.startswith("benchmark:")][:1] + [
        key for key in fresh_rows if key.startswith("memory:")
    ][:1]
    assert len(units) == 2
    compared = decided = 0
    for unit in units:
        shipped = {row["id"]: row for row in shipped_rows[unit]}
        fresh = {row["id"]: row for row in fresh_rows[unit]}
        assert sorted(shipped) == sorted(fresh)
        if {row["ranking"]["model"] for row in shipped.values()} == {None}:  # data/ is not ranked
            assert all(row["ranking"]["scored"] == [] for row in shipped.values())
            return
        for row_id, row in shipped.items():
            ours, theirs = row["ranking"], fresh[row_id]["ranking"]
            assert ours["model"] == theirs["model"], row_id
            assert [e["seed"] for e in ours["scored"]] == [e["seed"] for e in theirs["scored"]], row_id
            recorded = [e["score"] for e in ours["scored"]]
            scored = [e["score"] for e in theirs["scored"]]
            for a, b in zip(recorded, scored, strict=True):
                assert abs(a - b) < MACHINE_NOISE, (row_id, a, b)
                compared += 1
            # Each score and the best may each move by the noise, so a candidate's distance to the threshold
            # (best - margin) by twice that: beyond it, the choice cannot change.
            threshold = max(recorded) - margin
            if all(abs(score - threshold) > 2 * MACHINE_NOISE for score in recorded if score != max(recorded)):
                assert choose(scored, margin) == choose(recorded, margin), row_id
                decided += 1
    assert compared >= 100 and decided >= 10, (compared, decided)


def test_the_validation_reads_which_model_ranked_a_folder(ranked: BuildResult) -> None:
    from builders.validation.dataset import ranking_models

    stats = json.loads((ranked.folder / "build_stats.json").read_text())
    assert ranking_models(ranked.folder) == [stats["build"]["rank_model"]]
    shipped = json.loads((DATA / "build_stats.json").read_text())["build"]["rank_model"]
    assert ranking_models(DATA) == ([shipped] if shipped else [])


def test_the_replay_command_writes_the_folder_and_refuses_bad_settings(
    ranked: BuildResult, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from talkdem.cli import main

    assert main(["replay", str(ranked.folder), "--out", str(tmp_path / "again")]) == 0
    assert dataset_files(tmp_path / "again") == dataset_files(ranked.folder)
    assert main(["replay", str(ranked.folder), "--out", str(tmp_path / "wide"), "--rank-margin", "1000"]) == 0
    assert json.loads((tmp_path / "wide" / "build_stats.json").read_text())["build"]["rank_margin"] == 1000.0
    capsys.readouterr()
    for args, problem in [
        (["--out", str(ranked.folder)], "--out is SOURCE"),
        (["--out", str(tmp_path / "neg"), "--rank-margin", "-0.5"], "--rank-margin must be a number >= 0"),
        (["--out", str(tmp_path / "nan"), "--rank-margin", "nan"], "--rank-margin must be a number >= 0"),
    ]:
        assert main(["replay", str(ranked.folder), *args]) == 2
        err = capsys.readouterr().err.strip()
        assert len(err.splitlines()) == 1 and problem in err, err
    assert main(["replay", str(tmp_path / "nothing-here"), "--out", str(tmp_path / "x")]) == 2
    assert "no build settings to replay" in capsys.readouterr().err
