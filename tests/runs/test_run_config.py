"""The run configuration: built from a mapping (a sweep's YAML values) with every value typed and a bad one named
by its key; written back as `talkdem run` arguments that the command reads as the same configuration."""

from __future__ import annotations

from pathlib import Path

import pytest

from talkdem.cli import build_parser
from talkdem.cli.run import config_of
from talkdem.runs.config import RunConfig, RunConfigError

SETTINGS: dict[str, object] = {
    "model": "m",
    "backend": "openai",
    "model_args": {"tokenizer": "smollm2-135m-instruct", "timeout": 90, "add_bos": "never"},
    "base_urls": ["http://127.0.0.1:9/v1", "http://127.0.0.1:8/v1"],
    "concurrency": 2,
    "strategy": "care",
    "strategy_args": {"order": "best_first", "dedupe": True},
    "planner": "scoring",
    "max_steps": "7",
    "feedback": "both",
    "clarify": "oracle",
    "clarify_budget": 3,
    "conditions": "clean,intrusion:1",
    "limit": 2,
    "shard": "1/2",
    "out": "runs/x",
    "progress": False,
}


def test_a_mapping_is_typed_setting_by_setting() -> None:
    config = RunConfig.from_mapping(SETTINGS)
    assert config.model_args == {"tokenizer": "smollm2-135m-instruct", "timeout": 90.0, "add_bos": False}
    assert config.strategy_args == {"order": "best_first", "dedupe": True}
    assert config.base_urls == ("http://127.0.0.1:9/v1", "http://127.0.0.1:8/v1")
    assert config.max_steps == 7 and config.out == Path("runs/x") and config.questions == 3
    assert RunConfig.from_mapping({}) == RunConfig() and RunConfig().questions == 0


def test_its_arguments_are_the_same_run_to_the_command() -> None:
    config = RunConfig.from_mapping(SETTINGS)
    assert config_of(build_parser().parse_args(["run", *config.arguments()])) == config
    assert RunConfig().arguments() == ["--model", "default", "--backend", "llamacpp", "--strategy", "vanilla"]


@pytest.mark.parametrize(
    ("change", "key", "problem"),
    [
        ({"max_steps": 0}, "max_steps", "must be at least 1, got 0"),
        ({"log_top": "-1"}, "log_top", "must be 0 or more, got -1"),
        ({"limit": "many"}, "limit", "'many' is not a whole number"),
        ({"feedback": "loud"}, "feedback", "invalid choice: 'loud' (choose from mask, message, both, none)"),
        ({"no_mask_failed": True}, "no_mask_failed", "not a run setting"),
        ({"max_steps": [4]}, "max_steps", "expected a value (text or a number), got a list"),
        ({"backend": "gpt"}, "backend", "expected one of hf, llamacpp, vllm, openai"),
        ({"strategy": "vanila"}, "strategy", "(did you mean 'vanilla'?)"),
        ({"model_args": {"n_ctx": 9}}, "model_args.n_ctx", "the openai backend has no such option"),
        ({"model_args": {"timeout": 0}}, "model_args.timeout", "'timeout' takes a number above 0"),
        ({"strategy_args": {"order": "last"}}, "strategy_args.order", "takes one of best_first, best_last"),
        ({"strategy_args": {"chat": False}}, "strategy_args.chat", "(its options: order, dedupe); cot and tocc"),
        ({"strategy_args": ["order"]}, "strategy_args", "expected a mapping (key: value), got a list"),
        ({"threads": 2}, "threads", "not a run setting"),
    ],
)
def test_a_bad_setting_is_named_by_its_key(change: dict[str, object], key: str, problem: str) -> None:
    with pytest.raises(RunConfigError) as refused:
        RunConfig.from_mapping({**SETTINGS, **change})
    assert refused.value.key == key and problem in refused.value.problem, str(refused.value)


def test_a_budget_without_clarification_is_refused() -> None:
    with pytest.raises(ValueError, match="--clarify-budget applies with --clarify oracle or in-pattern"):
        RunConfig.from_mapping({"clarify_budget": 2})
