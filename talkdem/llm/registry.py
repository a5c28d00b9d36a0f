"""Backends registered by name as `module:Class`, imported only when asked for."""

from __future__ import annotations

import difflib
import importlib
from typing import Any

from talkdem.llm.base import LanguageModel

__all__ = ["BACKENDS", "UnknownBackendError", "load_model"]

BACKENDS: dict[str, str] = {
    "hf": "talkdem.llm.hf:HFCausalLM",
    "llamacpp": "talkdem.llm.llamacpp:LlamaCppLM",
    "vllm": "talkdem.llm.vllm_backend:VLLMLM",
    "openai": "talkdem.llm.openai_compat:OpenAICompatibleLM",
}


class UnknownBackendError(ValueError):
    pass


def load_model(backend: str, model: str, **options: Any) -> LanguageModel:
    """Instantiate backend `backend` on `model` (a path, model id or served name)."""
    if backend not in BACKENDS:
        close = difflib.get_close_matches(backend, BACKENDS, n=1)
        hint = f"; did you mean '{close[0]}'?" if close else ""
        raise UnknownBackendError(f"unknown backend '{backend}' (known: {', '.join(sorted(BACKENDS))}){hint}")
    module_name, class_name = BACKENDS[backend].split(":")
    cls = getattr(importlib.import_module(module_name), class_name)
    instance: LanguageModel = cls(model, **options)
    return instance
