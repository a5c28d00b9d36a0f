"""Replaying a dataset's ranking choices: the shipped data is what the builder writes, without hours of ranking;
a row the generator no longer draws shows up; the ranking model still makes the shipped choices."""

from __future__ import annotations

import json
import math
import shutil
from pathlib import Path

import pyarrow as pa
import pyarrow.parquet as pq
import pytest

from builders.build import BuildResult, build, dataset_files
from builders.generation.ranking import RecordedRanker, load_ranker
from builders.replay import recorded_rows, replay
from talkdem.paths import repo_root

DATA = repo_root() / "data"
RANK_MODEL = "qwen2.5-coder-0.5b"
NEAR_TIE = 1e-3
"""Nats per token: llama.cpp's scores move in the last digits with CPU kernels and threads; a choice between two
candidates closer than this may go either way on another machine."""


@pytest.fixture(scope="module")
def ranked(tmp_path_factory: pytest.TempPathFactory) -> BuildResult:
    """The first benchmark task and the first memory task, ranked by the default planner model (as data/ is)."""
    root = tmp_path_factory.mktemp("ranked")
    return build(root / "data", checkpoint=root / "c.jsonl", progress=False, limit=1, rank_model=RANK_MODEL)


def test_recorded_ranker_scores_the_kept_text_and_nothing_else() -> None:
    rows = [
        {"instruction": "Put the mug away.", "ranking": {"model": "m@1", "score": -2.5}},
        {"instruction": "Er, the mug.", "ranking": {"model": None, "score": None}},  # kept failing: no choice
    ]
    ranker = RecordedRanker.from_rows(rows)
    assert ranker is not None and ranker.model_id == "m@1"
    assert ranker.scores(["Er, the mug.", "Put the mug away."]) == [-math.inf, -2.5]
    assert RecordedRanker.from_rows(rows[1:]) is None
    with pytest.raises(ValueError, match="more than one model"):
        RecordedRanker.from_rows([*rows, {"instruction": "x", "ranking": {"model": "n@2", "score": -1.0}}])


def test_a_ranked_build_replays_to_the_same_bytes(ranked: BuildResult, tmp_path: Path) -> None:
    stats = replay(ranked.folder, tmp_path / "replayed")
    assert stats["build"]["rank_model"].startswith(f"llamacpp:{RANK_MODEL}@")
    assert dataset_files(tmp_path / "replayed") == dataset_files(ranked.folder)
    # the rows read back are the build's own (class labels by name, nulls kept), ready to build from
    from builders.build import build_unit
    from builders.generation import get_generator
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


def test_the_ranking_model_makes_the_shipped_choices(ranked: BuildResult) -> None:
    task_id = json.loads((DATA / "tasks" / "benchmark.jsonl").read_text().splitlines()[0])["task_id"]
    shipped = {row["id"]: row for row in recorded_rows(DATA)[f"benchmark:{task_id}"]}
    fresh = {row["id"]: row for row in recorded_rows(ranked.folder)[f"benchmark:{task_id}"]}
    assert sorted(shipped) == sorted(fresh)
    shipped_model = {row["ranking"]["model"] for row in shipped.values()}
    if shipped_model == {None}:  # data/ unranked: every row keeps its first verified candidate
        assert all(row["ranking"]["score"] is None for row in shipped.values())
        return
    ranker = load_ranker(RANK_MODEL)
    assert ranker is not None
    chosen = [row for row in shipped.values() if row["ranking"]["model"] is not None]
    assert len(chosen) >= 12 and {row["ranking"]["model"] for row in chosen} == {ranker.model_id}
    for row in chosen:
        again = fresh[row["id"]]
        if again["seed"] != row["seed"]:  # only a near tie may go the other way on this machine
            ours, theirs = ranker.scores([row["instruction"], again["instruction"]])
            assert abs(ours - theirs) < NEAR_TIE, (row["id"], row["instruction"], again["instruction"])
        else:
            assert again["instruction"] == row["instruction"]
            assert abs(again["ranking"]["score"] - row["ranking"]["score"]) < NEAR_TIE


def test_the_validation_reads_which_model_ranked_a_folder(ranked: BuildResult) -> None:
    from builders.validation.dataset import ranking_models

    stats = json.loads((ranked.folder / "build_stats.json").read_text())
    assert ranking_models(ranked.folder) == [stats["build"]["rank_model"]]
    shipped = json.loads((DATA / "build_stats.json").read_text())["build"]["rank_model"]
    assert ranking_models(DATA) == ([shipped] if shipped else [])
