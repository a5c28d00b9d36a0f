"""`talkdem import-inspect` on logs of the TALK-Dem inspect task made with a scripted mock model: every field
it reads is checked with one line naming the log, the sample and what was expected; the run's status says
whether every planned episode is there; a log of several epochs is imported one epoch at a time; and
docs/agents.md's flow (a log of `-T conditions=intrusion:3`, then `talkdem report`) works as written."""

from __future__ import annotations

import json
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest
from inspect_ai import eval as inspect_eval
from inspect_ai.log import EvalLog, read_eval_log, write_eval_log
from inspect_ai.model import ModelOutput, ModelUsage, get_model

from talkdem.cli import main
from talkdem.env import select
from talkdem.evals.inspect_task import talkdem
from talkdem.runs import read_episodes, read_header
from talkdem.tasks import get_task


def _act(skill: str) -> ModelOutput:
    output = ModelOutput.for_tool_call("mockllm/model", "act", {"skill": skill})
    output.usage = ModelUsage(input_tokens=1, output_tokens=1, total_tokens=2)  # no tokenizer download
    return output


def _scripted(plans: list[tuple[str, ...]]) -> list[ModelOutput]:
    return [_act(skill) for plan in plans for skill in plan]


def _done_forever() -> Iterator[ModelOutput]:
    while True:
        yield _act("done")


def _eval(folder: Path, outputs: Any, **options: Any) -> Path:
    """Run the task with a scripted model (samples in order: max_samples=1) and return the log file."""
    task_args = {k: options.pop(k) for k in ("conditions", "limit") if k in options}
    model = get_model("mockllm/model", custom_outputs=outputs)
    (log,) = inspect_eval(
        talkdem(**task_args), model=model, log_dir=str(folder), display="none", max_samples=1, **options
    )
    return Path(log.location)


@pytest.fixture(scope="module")
def clean_log(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Two clean episodes: the first played with its reference plan (C), the second stopping at once (I)."""
    first, _ = select("clean", limit=2)
    outputs = _scripted([get_task(first.task_id).reference_plan, ("done",)])
    return _eval(tmp_path_factory.mktemp("clean"), outputs, conditions="clean", limit=2)


@pytest.fixture(scope="module")
def two_epochs(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return _eval(tmp_path_factory.mktemp("epochs"), _done_forever(), conditions="clean", limit=2, epochs=2)


def _edited(log_file: Path, folder: Path, edit: Callable[[EvalLog], None]) -> Path:
    log = read_eval_log(str(log_file))
    edit(log)
    out = folder / "edited.eval"
    write_eval_log(log, str(out))
    return out


def _refused(argv: list[str], capsys: pytest.CaptureFixture[str]) -> str:
    """The CLI's one-line refusal (exit 2, no traceback, not an 'unexpected' error)."""
    assert main(argv) == 2
    error = capsys.readouterr().err
    assert error.count("\n") == 1 and "Traceback" not in error and "unexpected" not in error, error
    return error


def _task_args(**changes: object) -> Callable[[EvalLog], None]:
    return lambda log: log.eval.task_args.update(changes)


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        # the example: was "invalid literal for int() with base 10: 'abc'", naming neither log nor field
        (_task_args(max_steps="abc"), "task argument 'max_steps' must be a whole number, at least 1, got 'abc'"),
        (_task_args(max_steps=None), "task argument 'max_steps' must be a whole number, at least 1, got None"),
        (_task_args(max_steps=[3]), "task argument 'max_steps' must be a whole number, at least 1, got [3]"),
        (_task_args(max_steps=0), "task argument 'max_steps' must be a whole number, at least 1, got 0"),
        (_task_args(max_steps=2.5), "task argument 'max_steps' must be a whole number, at least 1, got 2.5"),
        (_task_args(max_steps=True), "task argument 'max_steps' must be a whole number, at least 1, got True"),
        (_task_args(limit="abc"), "task argument 'limit' must be a whole number of tasks, at least 1 (or none)"),
        (_task_args(limit=-2), "task argument 'limit' must be a whole number of tasks, at least 1 (or none), got -2"),
        (_task_args(conditions=5), "task argument 'conditions' must be text such as 'clean,intrusion:3', got 5"),
        (_task_args(conditions=["clean", 3]), "task argument 'conditions' must be text"),
        (_task_args(conditions="clean:1"), "task argument 'conditions': condition 'clean:1': clean has no levels"),
        (_task_args(conditions="shouting"), "task argument 'conditions': unknown condition 'shouting'"),
        (_task_args(limit=3), "the log's dataset has 2 samples, but its task arguments (conditions=clean, limit=3)"),
    ],
)
def test_task_arguments_of_the_wrong_kind_are_one_line_naming_the_log(
    clean_log: Path,
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    edit: Callable[[EvalLog], None],
    message: str,
) -> None:
    log = _edited(clean_log, tmp_path, edit)
    error = _refused(["import-inspect", str(log), "--out", str(tmp_path / "run")], capsys)
    assert f"{log}: " in error and message in error
    assert not (tmp_path / "run").exists()  # refused before the run directory is made


def _sample(index: int, **changes: Any) -> Callable[[EvalLog], None]:
    def edit(log: EvalLog) -> None:
        assert log.samples
        sample = log.samples[index]
        for name, value in changes.items():
            if name == "plan":
                sample.store["talkdem_plan"] = value
            elif name == "no_plan":
                del sample.store["talkdem_plan"]
            elif name == "score":
                assert sample.scores
                sample.scores["goal_check"].value = value
            elif name == "no_score":
                sample.scores = {}
            else:
                sample.metadata[name] = value

    return edit


def _second_is_first(log: EvalLog) -> None:
    assert log.samples
    log.samples[1].metadata["episode_id"] = log.samples[0].metadata["episode_id"]


@pytest.mark.parametrize(
    ("edit", "field", "message"),
    [
        (_sample(0, episode_id=5), "", "the sample has no TALK-Dem episode id (metadata.episode_id), got 5"),
        (_sample(0, episode_id="nonsense"), "", "metadata.episode_id: 'nonsense' is not an instruction id"),
        (_sample(0, episode_id="no_such_task:clean"), "", "episode 'no_such_task:clean' is not one the log's task"),
        (_sample(1, episode_id=select("intrusion:2", 1)[0].id), "", "is not one the log's task arguments select"),
        (_second_is_first, "", "again (first as sample"),
        (_sample(0, plan="find a mug"), ", store.talkdem_plan", "a plan must be a list of skill strings"),
        (_sample(0, plan=["done", 7]), ", store.talkdem_plan", ""),
        (_sample(0, no_plan=True), "", "no 'talkdem_plan' in the sample's store"),
        (_sample(0, score=1), "", "the goal_check score must be 'C' or 'I', got 1"),
        (_sample(0, score="X"), "", "the goal_check score must be 'C' or 'I', got 'X'"),
        (_sample(0, no_score=True), "", "no 'goal_check' score"),
        (_sample(0, score="I"), "", "the log scores it not successful, but its"),
    ],
)
def test_sample_fields_of_the_wrong_kind_are_one_line_naming_the_sample(
    clean_log: Path,
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    edit: Callable[[EvalLog], None],
    field: str,
    message: str,
) -> None:
    log = _edited(clean_log, tmp_path, edit)
    error = _refused(["import-inspect", str(log), "--out", str(tmp_path / "run")], capsys)
    assert f"{log}, sample " in error and f"{field}: " in error and message in error
    assert not (tmp_path / "run").exists()  # every sample is checked before anything is written


def test_a_log_field_inspect_cannot_read_names_the_field(
    clean_log: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    log = read_eval_log(str(clean_log))
    write_eval_log(log, str(tmp_path / "log.json"), format="json")
    data = json.loads((tmp_path / "log.json").read_text())
    data["samples"][0]["epoch"] = "first"
    (tmp_path / "log.json").write_text(json.dumps(data))
    error = _refused(["import-inspect", str(tmp_path / "log.json"), "--out", str(tmp_path / "run")], capsys)
    assert "not a readable inspect log (field samples.0.epoch:" in error and "'first'" in error


@pytest.mark.parametrize(
    ("arguments", "message"),
    [
        ({"max_steps": "abc"}, "task argument 'max_steps' must be a whole number, at least 1, got 'abc'"),
        ({"limit": "six"}, "task argument 'limit' must be a whole number of tasks"),
        ({"conditions": "clean:1"}, "condition 'clean:1': clean has no levels"),
        ({"conditions": ["clean", "intrusion:9"]}, "condition 'intrusion:9': the level must be 1, 2 or 3"),
    ],
)
def test_the_task_refuses_the_same_arguments_where_inspect_passes_them(arguments: Any, message: str) -> None:
    with pytest.raises(ValueError, match="talkdem inspect task") as info:
        talkdem(**arguments)
    assert message in str(info.value)


def test_a_complete_import_says_complete_and_a_resume_keeps_it(
    clean_log: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    run = tmp_path / "run"
    assert main(["import-inspect", str(clean_log), "--out", str(run)]) == 0
    assert "the run is complete (2 of 2 planned episodes)" in capsys.readouterr().out
    header = read_header(run)
    assert header.status == "complete" and header.config["planned_episodes"] == 2
    assert header.config["conditions"] == ["clean"] and header.config["limit"] == 2
    assert "epoch" not in header.config["inspect"]  # a one-epoch log's header is as before
    assert main(["import-inspect", str(clean_log), "--out", str(run)]) == 0  # nothing new: still complete
    assert "0 episodes imported" in capsys.readouterr().out and read_header(run).status == "complete"
    assert len(read_episodes(run)) == 2


def test_errored_and_unrun_samples_leave_the_run_incomplete(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    first, second = select("clean", limit=2)
    # the model runs out of answers during the second sample: inspect records an error instead of a score
    errored = _eval(
        tmp_path / "errored", _scripted([get_task(first.task_id).reference_plan]), limit=2, fail_on_error=False
    )
    assert main(["import-inspect", str(errored), "--out", str(tmp_path / "a")]) == 0
    out = capsys.readouterr().out
    assert "1 errored samples left out; the run is incomplete (1 of 2 planned episodes)" in out
    assert read_header(tmp_path / "a").status == "incomplete"
    assert [r.episode_id for r in read_episodes(tmp_path / "a")] == [first.id]
    # inspect --sample-id (or --limit) runs part of the dataset: the task's selection is still what the run plans
    part = _eval(tmp_path / "part", _scripted([get_task(first.task_id).reference_plan]), limit=2, sample_id=first.id)
    assert main(["import-inspect", str(part), "--out", str(tmp_path / "b")]) == 0
    header = read_header(tmp_path / "b")
    assert header.status == "incomplete" and header.config["planned_episodes"] == 2
    assert second.id not in {r.episode_id for r in read_episodes(tmp_path / "b")}


def test_a_log_of_two_epochs_is_refused_without_an_epoch(
    two_epochs: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    error = _refused(["import-inspect", str(two_epochs), "--out", str(tmp_path / "run")], capsys)
    assert "the log holds 2 epochs of each sample (inspect eval --epochs 2)" in error
    assert "--epoch N (1 to 2)" in error and not (tmp_path / "run").exists()
    error = _refused(["import-inspect", str(two_epochs), "--epoch", "3", "--out", str(tmp_path / "run")], capsys)
    assert "--epoch 3: the log holds epochs 1 to 2" in error


def test_each_epoch_imports_into_its_own_run(
    two_epochs: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    wanted = [i.id for i in select("clean", limit=2)]
    for epoch in (1, 2):
        run = tmp_path / f"epoch{epoch}"
        assert main(["import-inspect", str(two_epochs), "--epoch", str(epoch), "--out", str(run)]) == 0
        assert f"2 episodes of epoch {epoch} imported" in capsys.readouterr().out
        header = read_header(run)
        assert header.config["inspect"]["epoch"] == epoch and header.status == "complete"
        records = read_episodes(run)
        assert [r.episode_id for r in records] == wanted
        assert {r.notes["inspect_sample"] for r in records} == set(wanted) and all(r.plan == ("done",) for r in records)
    # another epoch into a run of the first is another run: refused, not mixed, and that run left as it was
    error = _refused(["import-inspect", str(two_epochs), "--epoch", "2", "--out", str(tmp_path / "epoch1")], capsys)
    assert f"{tmp_path / 'epoch1'} holds a different run (config.inspect:" in error
    header = read_header(tmp_path / "epoch1")
    assert header.config["inspect"]["epoch"] == 1 and header.status == "complete"


def test_an_epoch_of_a_one_epoch_log(clean_log: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    error = _refused(["import-inspect", str(clean_log), "--epoch", "2", "--out", str(tmp_path / "run")], capsys)
    assert "--epoch 2: the log holds one epoch (1)" in error
    assert main(["import-inspect", str(clean_log), "--epoch", "1", "--out", str(tmp_path / "run")]) == 0
    assert "epoch" not in read_header(tmp_path / "run").config["inspect"]
    with pytest.raises(SystemExit):  # argparse refuses it before the command starts
        main(["import-inspect", str(clean_log), "--epoch", "0", "--out", str(tmp_path / "r")])
    assert "--epoch: must be at least 1, got 0" in capsys.readouterr().err


def test_the_readme_flow_a_pattern_only_log_then_report(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """docs/agents.md: `inspect eval ... -T conditions=intrusion:3 -T limit=6`, `talkdem import-inspect`,
    `talkdem report` (limit 2 here). The report used to stop at retention, pointing to a `retention=False` the CLI
    lacks."""
    episodes = select("intrusion:3", limit=2)
    plans = [get_task(e.task_id).reference_plan for e in episodes]
    log = _eval(tmp_path / "logs", _scripted(plans), conditions="intrusion:3", limit=2)
    run = tmp_path / "runs" / "smollm2-inspect"
    assert main(["import-inspect", str(log), "--out", str(run)]) == 0
    assert read_header(run).status == "complete"
    capsys.readouterr()
    assert main(["report", str(run), "--out", str(tmp_path / "report"), "--no-plots", "--bootstrap", "0"]) == 0
    error = capsys.readouterr().err
    assert f"{run}: retention left out: 2 pattern episode(s) have no clean episode of their task" in error
    assert "include clean in the run's conditions" in error and "retention=False" not in error
    (scores_file,) = (tmp_path / "report" / "scores").glob("*.json")
    scores = json.loads(scores_file.read_text())
    assert scores["retention"] is None and scores["success_rate"]["intrusion:3"] == 1.0


def test_a_log_with_no_scored_sample_is_refused(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    # every sample errored (here: the model has no answer; offline, a provider that cannot reach its tokenizer)
    log = _eval(tmp_path / "logs", [], conditions="clean", limit=1, fail_on_error=False)
    error = _refused(["import-inspect", str(log), "--out", str(tmp_path / "run")], capsys)
    assert f"{log}: no scored sample to import (1 errored, the first: " in error
    assert "custom_outputs ran out of values" in error and not (tmp_path / "run").exists()
