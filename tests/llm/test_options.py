"""Backend options as data: the parser types `key=value` text through a backend's declaration and refuses an
unknown key or a bad value with one line naming the option, the backend and what it accepts; every backend's
declaration names real constructor keywords whose defaults parse back to themselves."""

from __future__ import annotations

import inspect

import pytest

from talkdem.llm.interface.options import BackendOption, parse_model_args
from talkdem.llm.interface.registry import BACKENDS, backend_options, model_args

DECLARED = (
    BackendOption("threads", "int", minimum=1),
    BackendOption("timeout", "float", minimum=0, above_minimum=True),
    BackendOption("chat_template", "bool"),
    BackendOption("tokenizer", "str"),
    BackendOption("add_bos", "choice", choices={"model": None, "always": True, "never": False}),
)


def test_values_are_typed_by_the_declaration() -> None:
    parsed = parse_model_args(
        "x", DECLARED, ["threads=3", "timeout=2.5", "chat_template=false", "tokenizer=a=b", "add_bos=never"]
    )
    assert parsed == {"threads": 3, "timeout": 2.5, "chat_template": False, "tokenizer": "a=b", "add_bos": False}
    assert type(parsed["threads"]) is int and type(parsed["timeout"]) is float
    assert parse_model_args("x", DECLARED, ["add_bos=model", "chat_template=TRUE"]) == {
        "add_bos": None,
        "chat_template": True,
    }


@pytest.mark.parametrize(
    ("item", "message"),
    [
        ("thread=2", "model arg 'thread': the x backend has no such option (its options: threads, timeout,"),
        ("threads=0", "model arg threads='0': the x backend's 'threads' takes a whole number of at least 1"),
        ("threads=two", "the x backend's 'threads' takes a whole number of at least 1"),
        ("timeout=0", "the x backend's 'timeout' takes a number above 0"),
        ("timeout=nan", "the x backend's 'timeout' takes a number above 0"),
        ("chat_template=maybe", "the x backend's 'chat_template' takes true or false"),
        ("add_bos=sometimes", "the x backend's 'add_bos' takes one of model, always, never"),
        ("tokenizer=", "the x backend's 'tokenizer' takes a non-empty string"),
        ("threads", "--model-arg 'threads': expected KEY=VALUE"),
        ("=3", "--model-arg '=3': expected KEY=VALUE"),
    ],
)
def test_a_bad_item_is_one_line_naming_option_and_backend(item: str, message: str) -> None:
    with pytest.raises(ValueError) as refused:
        parse_model_args("x", DECLARED, [item])
    assert message in str(refused.value) and "\n" not in str(refused.value)


def test_a_key_given_twice_must_agree() -> None:
    assert parse_model_args("x", DECLARED, ["threads=2", "threads=2"]) == {"threads": 2}
    with pytest.raises(ValueError, match="'threads' given twice, as 2 and 3"):
        parse_model_args("x", DECLARED, ["threads=2", "threads=3"])


def test_text_is_the_inverse_of_parse() -> None:
    for option, value in [(DECLARED[4], None), (DECLARED[4], True), (DECLARED[2], False), (DECLARED[0], 4)]:
        assert option.parse(option.text(value)) == value


@pytest.mark.parametrize("backend", ["hf", "llamacpp", "vllm", "openai"])  # the shipped ones (tests register more)
def test_every_declared_option_is_a_constructor_keyword_with_a_parsable_default(backend: str) -> None:
    parameters = inspect.signature(BACKENDS.factory(backend)).parameters
    extra = any(p.kind is inspect.Parameter.VAR_KEYWORD for p in parameters.values())
    declared = backend_options(backend)
    assert declared, f"{backend} declares no option"
    for option in declared:
        if option.name not in parameters:
            assert extra, f"{backend}: '{option.name}' is no keyword of its constructor"
            continue
        default = parameters[option.name].default
        if default is not None and default is not inspect.Parameter.empty:
            assert option.parse(option.text(default)) == default, (backend, option.name)


def test_the_registry_reads_each_backends_own_declaration() -> None:
    assert model_args("llamacpp", ["n_ctx=2048", "f32_kv_cache=no"]) == {"n_ctx": 2048, "f32_kv_cache": False}
    with pytest.raises(ValueError, match=r"the hf backend has no such option \(its options: device, dtype,"):
        model_args("hf", ["n_ctx=2048"])
    with pytest.raises(ValueError, match="the openai backend's 'endpoint' takes one of chat, completions, auto"):
        model_args("openai", ["endpoint=web"])
