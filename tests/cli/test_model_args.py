"""`talkdem run --model-arg KEY=VALUE`: backend options checked by the backend's own declaration, recorded in the
header as the flags that were once shorthand for them recorded them; a removed shorthand names its replacement."""

from __future__ import annotations

from pathlib import Path

import pytest

from talkdem.cli import build_parser, main
from talkdem.cli.run import config_of
from talkdem.llm.interface.models import FAST_TEST_MODEL
from talkdem.runs.plan import RunPlan, plan_run

SMALL = ["--limit", "1", "--conditions", "clean"]


def _plan(*argv: str) -> RunPlan:
    return plan_run(config_of(build_parser().parse_args(["run", *SMALL, *argv])))


def test_model_args_become_typed_constructor_options_and_are_recorded() -> None:
    plan = _plan("--backend", "llamacpp", "--model-arg", "n_ctx=2048", "--model-arg", "f32_kv_cache=false")
    assert plan.options == {"n_ctx": 2048, "f32_kv_cache": False}
    assert plan.backend_args == {"n_ctx": 2048, "f32_kv_cache": False}


def test_threads_are_a_model_arg_recorded_with_the_selection() -> None:
    plan = _plan("--backend", "llamacpp", "--model-arg", "threads=2")
    assert plan.options == {"threads": 2} and plan.extra["threads"] == 2
    assert _plan("--backend", "llamacpp", "--model-arg", "threads=2", "--model-arg", "threads=2").options == {
        "threads": 2
    }
    with pytest.raises(ValueError, match="model arg 'threads' given twice, as 2 and 3"):
        _plan("--backend", "llamacpp", "--model-arg", "threads=2", "--model-arg", "threads=3")


def test_the_served_options_record_what_their_old_flags_recorded() -> None:
    # The header of a run started when these options had flags of their own (--timeout 90 --tokenizer NAME
    # --bos never): these keys, in this order, with these values, whatever order they are given in.
    given = ["--model-arg", f"tokenizer={FAST_TEST_MODEL}", "--model-arg", "add_bos=never", "--model-arg", "timeout=90"]
    plan = _plan("--backend", "openai", "--model", "m", *given)
    assert plan.options == {
        "timeout": 90.0,
        "tokenizer": FAST_TEST_MODEL,
        "scoring_api": "completions",
        "prompt_format": "ids",
        "add_bos": False,
    }
    assert list(plan.backend_args.items()) == [
        ("timeout", 90.0),
        ("tokenizer", FAST_TEST_MODEL),
        ("scoring_api", "completions"),
        ("prompt_format", "ids"),
        ("bos", "never"),
    ]


def test_a_local_model_is_its_own_served_tokenizer_and_react_plain_text() -> None:
    plan = _plan("--backend", "openai", "--model", FAST_TEST_MODEL)
    assert plan.options["tokenizer"] == FAST_TEST_MODEL and plan.backend_args["bos"] == "model"
    generative = _plan(
        "--backend", "openai", "--model", "m", "--planner", "generative", "--model-arg", "add_bos=always"
    )
    assert generative.options == {}
    react = _plan("--backend", "hf", "--planner", "react", "--model-arg", "threads=1")
    assert list(react.options.items()) == [("chat_template", False), ("threads", 1)]
    with pytest.raises(ValueError, match="drop model arg chat_template"):
        _plan("--backend", "hf", "--planner", "react", "--model-arg", "chat_template=true")


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--backend", "hf", "--model-arg", "n_ctx=9"], "model arg 'n_ctx': the hf backend has no such option"),
        (["--backend", "llamacpp", "--model-arg", "n_ctx=big"], "'n_ctx' takes a whole number of at least 1"),
        (["--backend", "hf", "--model-arg", "tokenizer=x"], "model arg 'tokenizer': the hf backend has no such option"),
        (["--backend", "vllm", "--model-arg", "threads=5"], "model arg 'threads': the vllm backend has no such option"),
        (["--backend", "hf", "--base-url", "http://127.0.0.1:9/v1"], "--base-url is for --backend openai"),
        (["--backend", "llamacpp", "--model-arg", "sequences=0"], "'sequences' takes a whole number of at least 1"),
        (["--backend", "openai", "--model", "m"], "scoring through a server needs the served model's tokenizer"),
    ],
)
def test_a_bad_model_arg_is_one_line_and_exit_2(
    argv: list[str], message: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["run", *SMALL, *argv, "--out", str(tmp_path / "r"), "--no-progress"]) == 2
    error = capsys.readouterr().err
    assert message in error and error.count("\n") == 1 and "Traceback" not in error, error
    assert not (tmp_path / "r").exists()


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--tokenizer", "x"], "--tokenizer was removed: use --model-arg tokenizer=x"),
        (["--scoring-api", "sglang"], "--scoring-api was removed: use --model-arg scoring_api=sglang"),
        (["--prompt-format", "text"], "--prompt-format was removed: use --model-arg prompt_format=text"),
        (["--bos", "never"], "--bos was removed: use --model-arg add_bos=never"),
        (["--timeout", "90"], "--timeout was removed: use --model-arg timeout=90"),
        (["--threads", "2"], "--threads was removed: use --model-arg threads=2"),
    ],
)
def test_a_removed_shorthand_names_its_replacement(
    argv: list[str], message: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["run", *SMALL, *argv, "--out", str(tmp_path / "r"), "--no-progress"]) == 2
    error = capsys.readouterr().err
    assert error == f"talkdem run: error: {message}\n"
    assert not (tmp_path / "r").exists()


@pytest.mark.parametrize("planner_flags", [["--scoring", "mean"], ["--log-top", "5"]])
@pytest.mark.parametrize("batched", [["--concurrency", "4"], ["--model-arg", "sequences=4"]])
def test_scores_the_multi_sequence_context_does_not_compute_are_refused_with_it(
    planner_flags: list[str], batched: list[str]
) -> None:
    # Mean scores and logged top-N scores come from the serial context; a header naming the multi-sequence layout
    # would say they came from another.
    with pytest.raises(ValueError, match="score one episode at a time on llamacpp: run them with --concurrency 1"):
        _plan(*planner_flags, *batched)
    assert _plan(*planner_flags).options.get("sequences", 1) == 1  # serially they run
    assert _plan(*batched).options["sequences"] == 4  # and sum-scoring choices batch
