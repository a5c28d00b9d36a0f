"""`talkdem run --model-arg KEY=VALUE`: backend options checked by the backend's own declaration; the older
flags are shorthand for one, and record in the header what they always recorded."""

from __future__ import annotations

from pathlib import Path

import pytest

from talkdem.cli import build_parser, main
from talkdem.cli.run import RunPlan, plan_run
from talkdem.llm.interface.models import FAST_TEST_MODEL

SMALL = ["--limit", "1", "--conditions", "clean"]


def _plan(*argv: str) -> RunPlan:
    return plan_run(build_parser().parse_args(["run", *SMALL, *argv]))


def test_model_args_become_typed_constructor_options_and_are_recorded() -> None:
    plan = _plan("--backend", "llamacpp", "--model-arg", "n_ctx=2048", "--model-arg", "f32_kv_cache=false")
    assert plan.options == {"n_ctx": 2048, "f32_kv_cache": False}
    assert plan.backend_args == {"n_ctx": 2048, "f32_kv_cache": False}


def test_threads_by_flag_or_model_arg_are_one_setting() -> None:
    by_flag = _plan("--backend", "llamacpp", "--threads", "2")
    by_arg = _plan("--backend", "llamacpp", "--model-arg", "threads=2")
    assert by_flag.options == by_arg.options == {"threads": 2}
    assert by_flag.extra["threads"] == by_arg.extra["threads"] == 2
    assert _plan("--backend", "llamacpp", "--threads", "2", "--model-arg", "threads=2").options == {"threads": 2}
    with pytest.raises(ValueError, match="--threads 2 and --model-arg threads=3 disagree"):
        _plan("--backend", "llamacpp", "--threads", "2", "--model-arg", "threads=3")


def test_the_served_shorthands_record_what_they_always_recorded() -> None:
    # The header of a run started before --model-arg existed: these keys, in this order, with these values.
    old = ["--backend", "openai", "--model", "m", "--tokenizer", FAST_TEST_MODEL, "--timeout", "90", "--bos", "never"]
    plan = _plan(*old)
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
    as_args = _plan(
        "--backend", "openai", "--model", "m", "--model-arg", "add_bos=never", "--model-arg", "timeout=90",
        "--model-arg", f"tokenizer={FAST_TEST_MODEL}",
    )  # fmt: skip
    assert list(as_args.backend_args.items()) == list(plan.backend_args.items())


def test_a_local_model_is_its_own_served_tokenizer_and_react_plain_text() -> None:
    plan = _plan("--backend", "openai", "--model", FAST_TEST_MODEL)
    assert plan.options["tokenizer"] == FAST_TEST_MODEL and plan.backend_args["bos"] == "model"
    assert _plan("--backend", "openai", "--model", "m", "--planner", "generative", "--bos", "always").options == {}
    react = _plan("--backend", "hf", "--planner", "react", "--threads", "1")
    assert list(react.options.items()) == [("chat_template", False), ("threads", 1)]
    with pytest.raises(ValueError, match="drop model arg chat_template"):
        _plan("--backend", "hf", "--planner", "react", "--model-arg", "chat_template=true")


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--backend", "hf", "--model-arg", "n_ctx=9"], "model arg 'n_ctx': the hf backend has no such option"),
        (["--backend", "llamacpp", "--model-arg", "n_ctx=big"], "'n_ctx' takes a whole number of at least 1"),
        (["--backend", "hf", "--tokenizer", "x"], "--tokenizer applies to the openai backend, not hf"),
        (["--backend", "llamacpp", "--bos", "never"], "--bos applies to the openai backend, not llamacpp"),
        (["--backend", "vllm", "--timeout", "5"], "--timeout applies to the openai backend, not vllm"),
        (["--backend", "vllm", "--threads", "5"], "--threads applies to the hf and llamacpp backends, not vllm"),
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
