"""How the transformers backend lays a system message into a chat template, with a scripted tokenizer (the
real templates run in tests/dataset/test_llm_build.py and, through llama.cpp, test_llm_structured.py)."""

from __future__ import annotations

from typing import Any

import pytest

from talkdem.llm.backends.hf import HFCausalLM
from talkdem.llm.interface.requests import GenerateRequest


class TemplateError(Exception):
    """What jinja2 raises from a template's own `raise_exception` (Gemma's refuse a system role)."""


class Tokenizer:
    def __init__(self, accepts_system: bool) -> None:
        self.accepts_system = accepts_system
        self.calls: list[list[dict[str, str]]] = []

    def apply_chat_template(self, messages: list[dict[str, str]], **options: Any) -> str:
        self.calls.append(messages)
        if not self.accepts_system and any(m["role"] == "system" for m in messages):
            raise TemplateError("System role not supported")
        return "".join(f"<{m['role']}>{m['content']}" for m in messages) + "<assistant>"


def _backend(tokenizer: Tokenizer) -> HFCausalLM:
    backend = HFCausalLM.__new__(HFCausalLM)  # no model: only the template step is under test
    backend.tokenizer = tokenizer
    return backend


def test_the_system_message_goes_first_when_the_template_takes_one() -> None:
    request = GenerateRequest("Rewrite it.", system="You are a rewriter.")
    assert _backend(Tokenizer(True)).chat_text(request) == "<system>You are a rewriter.<user>Rewrite it.<assistant>"
    assert _backend(Tokenizer(True)).chat_text(GenerateRequest("Hi.")) == "<user>Hi.<assistant>"


def test_a_template_without_a_system_role_gets_it_at_the_head_of_the_user_message() -> None:
    tokenizer = Tokenizer(False)
    text = _backend(tokenizer).chat_text(GenerateRequest("Rewrite it.", system="You are a rewriter."))
    assert text == "<user>You are a rewriter.\n\nRewrite it.<assistant>" and len(tokenizer.calls) == 2


def test_other_template_errors_are_not_hidden() -> None:
    class Broken(Tokenizer):
        def apply_chat_template(self, messages: list[dict[str, str]], **options: Any) -> str:
            raise TemplateError("unexpected end of template")

    with pytest.raises(TemplateError, match="unexpected end"):
        _backend(Broken(True)).chat_text(GenerateRequest("Rewrite it.", system="You are a rewriter."))
