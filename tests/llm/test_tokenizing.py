"""The one BOS/encode rule of every backend that tokenizes here (hf, vllm, llamacpp, a served model's tokenizer):
a context starts with BOS by the model's own rule unless `add_bos` says always or never; a continuation never
does; the Hugging Face and the GGUF vocabulary of one model split a SayCan prompt alike."""

from __future__ import annotations

from typing import Any

import pytest

from talkdem.llm.backends.tokenizing import GGUFTokenSplit, HFTokenSplit, TokenSplit, bos_to_use
from talkdem.llm.interface.models import FAST_TEST_MODEL, model_path

CONTEXT = "Robot: Hi there, I'm a robot operating in a house.\nHuman: bring me an apple\nRobot: 1."
CONTINUATION = " find an apple"


@pytest.mark.parametrize(
    ("own_rule", "add_bos", "expected"),
    [
        (True, None, 7),  # model: its own rule
        (False, None, None),
        (False, True, 7),  # always
        (True, True, 7),
        (True, False, None),  # never
        (False, False, None),
    ],
)
def test_the_rule_is_the_models_own_unless_overridden(
    own_rule: bool, add_bos: bool | None, expected: int | None
) -> None:
    assert bos_to_use(7, own_rule, add_bos) == expected


def test_a_vocabulary_without_bos_never_gets_one() -> None:
    assert bos_to_use(None, True, None) is None and bos_to_use(None, False, True) is None


@pytest.fixture(scope="module")
def gguf_llm() -> Any:
    from llama_cpp import Llama

    return Llama(model_path=str(model_path(FAST_TEST_MODEL)), vocab_only=True, verbose=False)


@pytest.fixture(scope="module")
def hf_tokenizer() -> Any:
    from transformers import AutoTokenizer

    path = model_path(FAST_TEST_MODEL)
    return AutoTokenizer.from_pretrained(str(path.parent), gguf_file=path.name)


def _check_rule(model: TokenSplit, always: TokenSplit, never: TokenSplit, bos: int) -> None:
    plain = model.encode(CONTEXT)
    assert plain and bos not in plain[:1]
    assert model.context_ids(CONTEXT) == plain, "SmolLM2's own rule: no BOS"
    assert always.context_ids(CONTEXT) == [bos, *plain]
    assert never.context_ids(CONTEXT) == plain
    for split in (model, always, never):
        assert split.encode(CONTINUATION) == model.encode(CONTINUATION), "a continuation never gets BOS"


def test_gguf_split_follows_the_rule(gguf_llm: Any) -> None:
    splits = [GGUFTokenSplit(gguf_llm, add_bos) for add_bos in (None, True, False)]
    _check_rule(*splits, bos=int(gguf_llm.token_bos()))
    # The model's own rule is what llama.cpp applies when asked for special tokens.
    assert splits[0].context_ids(CONTEXT) == gguf_llm.tokenize(CONTEXT.encode(), add_bos=True, special=False)


def test_hf_split_follows_the_rule_and_splits_as_the_gguf(hf_tokenizer: Any, gguf_llm: Any) -> None:
    splits = [HFTokenSplit(hf_tokenizer, add_bos) for add_bos in (None, True, False)]
    _check_rule(*splits, bos=int(hf_tokenizer.bos_token_id))
    gguf = GGUFTokenSplit(gguf_llm)
    assert splits[0].context_ids(CONTEXT) == gguf.context_ids(CONTEXT)
    assert splits[0].encode(CONTINUATION) == gguf.encode(CONTINUATION)
    assert b"".join(splits[0].piece(t) for t in splits[0].encode(CONTINUATION)) == CONTINUATION.encode()
