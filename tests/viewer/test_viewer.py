"""The viewer's data: the instruction diff, safe embedding, no machine paths, chunking, the folder rule,
`--log-top` candidates kept in records and shown, and the CLI."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from metrics_helpers import BOOK, LAMP, clean_id, failing, pattern_id, reference
from viewer_browser import COMMITTED, chunk_of, drive, index_of

from talkdem.cli import main
from talkdem.runs import EpisodeRecord, EpisodeWriter, RunHeader, write_header
from talkdem.sim import run_plan
from talkdem.tasks import get_task
from talkdem.viewer import ViewerFiles, load_runs, script_json, word_diff, write_viewer

HOSTILE = "</script><script>document.title='injected'</script><!-- & \u2028"


def test_word_diff_marks_what_the_pattern_added() -> None:
    clean = "Put the mug in the sink, please."
    text = "Put the, um, thing, you know, the mug in the sink please."
    segments = word_diff(clean, text)
    assert "".join(t for kind, t in segments if kind != "del") == text  # the text is kept exactly
    inserted = " ".join(t.strip() for kind, t in segments if kind == "ins")
    assert inserted == "the, um, thing, you know,"
    assert all("mug" not in t for kind, t in segments if kind == "ins")  # "sink" vs "sink," still matches


@settings(max_examples=200, deadline=None)
@given(st.text(alphabet="ab ,.\n", max_size=40), st.text(alphabet="ab ,.\n", max_size=40))
def test_word_diff_keeps_the_text_and_the_clean_words(clean: str, text: str) -> None:
    segments = word_diff(clean, text)
    assert "".join(t for kind, t in segments if kind != "del") == text
    kept = " ".join(t for kind, t in segments if kind in ("same", "del")).split()
    assert len(kept) == len(clean.split())  # every clean word is shown once, shared or struck out


def test_word_diff_shows_replaced_clean_words() -> None:
    segments = word_diff("Bring the apple to the table.", "Bring the pear to the table.")
    assert ("del", "apple") in segments and ("ins", "pear ") in segments
    assert word_diff("Same words.", "same words") == [("same", "same words")]


def test_script_json_cannot_end_the_script() -> None:
    text = script_json({"x": HOSTILE})
    assert "<" not in text and ">" not in text and "&" not in text and "\u2028" not in text
    assert json.loads(text) == {"x": HOSTILE}


def _hostile_run(root: Path) -> Path:
    """A run whose model is a machine path and whose instruction and notes try to break out of the page."""
    run_dir = root / "runs" / "hostile"
    write_header(
        run_dir,
        RunHeader(
            model={"backend": "llamacpp", "name": str(root / "secret-models" / "tiny.Q8_0.gguf"), "revision": "r"},
            planner="saycan",
            strategy="care",
            prompt_version="test",
            dataset_hash="0" * 64,  # a sha256 digest, as headers are validated on read
            code_revision="test",
            config={"max_steps": 30},
        ),
    )
    plans = {clean_id(BOOK): reference(BOOK), pattern_id(BOOK, "intrusion", 2): failing(BOOK)}
    top = json.dumps([[["find a book", -0.5], [HOSTILE, -2.25]], [["pick up the book", float("-inf")]]])
    with EpisodeWriter(run_dir) as writer:
        for episode_id, plan in plans.items():
            trace = run_plan(get_task(BOOK), plan)
            instruction = f"Find the book {HOSTILE}"
            summary = trace.summary()
            writer.write(
                EpisodeRecord(
                    episode_id=episode_id,
                    task_id=BOOK,
                    pattern=episode_id.split(":")[1],
                    level=int(episode_id.split(":")[2]),
                    instruction=instruction,
                    plan=tuple(plan),
                    success=trace.success,
                    hazards=tuple(summary["hazards"]),
                    goal_conditions=summary["goal_conditions"],
                    trace=trace.to_json(),
                    notes={"retrieved": HOSTILE, "path": str(root / "home" / "notes.txt"), "top_candidates": top},
                )
            )
    return run_dir


@pytest.fixture(scope="module")
def hostile(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, ViewerFiles]:
    root = tmp_path_factory.mktemp("hostile")
    files = write_viewer(load_runs([_hostile_run(root)]), root / "viewer", chunk_size=1)
    return root, files


def test_embedded_strings_are_escaped_and_carry_no_machine_path(hostile: tuple[Path, ViewerFiles]) -> None:
    root, files = hostile
    for path in [files.page, files.index, *files.chunks]:
        text = path.read_text(encoding="utf-8")
        assert str(root) not in text and "secret-models" not in text and "/home/" not in text, path.name
        if path != files.page:
            assert "<" not in text and ">" not in text, path.name  # the data scripts hold no markup at all
    index = index_of(files.folder)
    assert index["runs"][0]["model"] == "tiny.Q8_0.gguf" and index["runs"][0]["run_dir"] == "hostile"
    detail = chunk_of(files.folder, 1)[0]
    assert detail["notes"] == {"retrieved": HOSTILE, "path": "notes.txt"}
    assert detail["top"] == [[["find a book", -0.5], [HOSTILE, -2.25]], [["pick up the book", None]]]


def test_hostile_text_is_shown_as_text_in_chromium(hostile: tuple[Path, ViewerFiles], tmp_path: Path) -> None:
    _, files = hostile
    steps = """
    key('j'); key('Enter');
    waitFor(opened, function(){
      out.title = document.title;
      out.cell = document.querySelector('#episodes tbody tr.sel td.instr').textContent;
      out.top = Array.from(document.querySelectorAll('#episode-body .col .top'))
        .map(function(t){ return t.textContent; });
      out.notes = document.querySelector('#episode-body dl.notes').textContent;
      finish();
    });
    """
    seen = drive(files.page, steps, tmp_path / "profile")
    assert seen["title"] == "TALK-Dem episodes"  # the injected script never ran
    assert seen["cell"] == f"Find the book {HOSTILE}"
    assert seen["top"][0] == f"find a book -0.50 · {HOSTILE} -2.25" and seen["top"][1] == "pick up the book ?"
    assert HOSTILE in seen["notes"]


def test_chunks_hold_consecutive_episodes(committed_viewer: ViewerFiles) -> None:
    index = index_of(committed_viewer.folder)
    assert index["chunks"] == len(committed_viewer.chunks) == 10  # 1,920 episodes, 200 per file
    f = {name: i for i, name in enumerate(index["fields"])}
    for number, path in enumerate(committed_viewer.chunks):
        assert path.name == f"chunk-{number:04d}.js"
        details = chunk_of(committed_viewer.folder, number)
        rows = index["rows"][number * 200 : (number + 1) * 200]
        assert len(details) == len(rows)
        for row, detail in zip(rows, details, strict=True):
            assert (detail["diff"] is None) == (row[f["pattern"]] == "clean")
            assert len(detail["steps"]) >= row[f["plan_length"]]


def test_the_folder_rule(tmp_path: Path, committed_runs: list) -> None:  # type: ignore[type-arg]
    other = tmp_path / "other"
    other.mkdir()
    (other / "keep.txt").write_text("mine")
    with pytest.raises(ValueError, match="not a viewer folder"):
        write_viewer(committed_runs, other)
    assert (other / "keep.txt").read_text() == "mine"
    out = tmp_path / "viewer"
    write_viewer(committed_runs, out, chunk_size=100)
    assert len(list((out / "data").glob("chunk-*.js"))) == 20
    write_viewer(committed_runs, out, chunk_size=400)  # rewriting its own folder replaces the old chunks
    assert len(list((out / "data").glob("chunk-*.js"))) == 5
    assert "sdk: static" in (out / "README.md").read_text()


def test_log_top_candidates_are_stored_in_the_record(tmp_path: Path) -> None:
    import sys

    sys.path.insert(0, str(Path(__file__).parent.parent / "planner"))
    from scripted_lm import ScriptedLM

    from talkdem.instructions import load_instructions
    from talkdem.planner.saycan import SayCanConfig
    from talkdem.planner.strategies import load_strategy
    from talkdem.runs import read_episodes
    from talkdem.runs.runner import run_episodes

    instruction = next(i for i in load_instructions() if i.id == clean_id(LAMP))
    script = [*reference(LAMP)]
    run_episodes(
        [instruction],
        ScriptedLM(script),
        load_strategy("vanilla"),
        tmp_path / "run",
        SayCanConfig(log_top=3),
        progress=False,
    )
    (record,) = read_episodes(tmp_path / "run")
    top = json.loads(record.notes["top_candidates"])
    assert len(top) == len(record.plan) and all(len(step) == 3 for step in top)
    assert [step[0][0] for step in top] == list(record.plan)  # the winner leads each step's list
    files = write_viewer(load_runs([tmp_path / "run"]), tmp_path / "viewer")
    assert chunk_of(files.folder, 0)[0]["top"] == top


def test_cli_view_and_sample(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    sample = tmp_path / "sample.json"
    assert main(["sample-errors", *map(str, COMMITTED), "--seed", "3", "--out", str(sample)]) == 0
    assert "89 failures, seed 3" in capsys.readouterr().out
    assert main(["view", *map(str, COMMITTED), "--sample", str(sample), "--out", str(tmp_path / "v")]) == 0
    out = capsys.readouterr().out
    assert "1920 episodes of 2 run(s), 89 in the error sample; 10 detail files" in out
    index = index_of(tmp_path / "v")
    assert sum(r[index["fields"].index("sampled")] for r in index["rows"]) == 89
    # A sample drawn from other runs is refused with one line naming the episode.
    assert main(["view", str(COMMITTED[0]), "--sample", str(sample), "--out", str(tmp_path / "w")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and re.search(r"error sample: episode \d+ \(qwen2.5-coder-0.5b / CARE / ", err)
    assert not (tmp_path / "w").exists()


def test_records_without_a_trace_show_the_re_execution(tmp_path: Path) -> None:
    from metrics_helpers import write_run

    plans = {clean_id(BOOK): reference(BOOK), pattern_id(BOOK, "topic_drift", 1): failing(BOOK)}
    files = write_viewer(load_runs([write_run(tmp_path / "run", plans)]), tmp_path / "viewer")
    details = chunk_of(files.folder, 0)
    for detail, plan in zip(details, plans.values(), strict=True):
        assert [s[0] for s in detail["steps"]] == plan and detail["end"] == "done"
        assert detail["goals"] and all(len(g) == 2 for g in detail["goals"])
    assert all(g[1] for g in details[0]["goals"]) and not all(g[1] for g in details[1]["goals"])
    index = index_of(files.folder)
    assert [r[index["fields"].index("error")] for r in index["rows"]] == ["", "subgoal_omission"]
