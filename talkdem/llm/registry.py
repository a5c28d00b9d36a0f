"""Backends registered by name as `module:Class`, imported only when asked for."""

from __future__ import annotations

from typing import Any

from talkdem.llm.base import LanguageModel
from talkdem.registry import Registry, UnknownNameError

__all__ = ["BACKENDS", "UnknownBackendError", "load_model"]

BACKENDS: Registry[LanguageModel] = Registry("backend")
BACKENDS.register("hf", "talkdem.llm.hf:HFCausalLM", "Hugging Face transformers")
BACKENDS.register("llamacpp", "talkdem.llm.llamacpp:LlamaCppLM", "llama.cpp")
BACKENDS.register("vllm", "talkdem.llm.vllm_backend:VLLMLM", "vLLM")
BACKENDS.register("openai", "talkdem.llm.openai_compat:OpenAICompatibleLM", "OpenAI-compatible server")

UnknownBackendError = UnknownNameError  # the name callers already catch


def load_model(backend: str, model: str, **options: Any) -> LanguageModel:
    """Instantiate backend `backend` on `model` (a path, model id or served name)."""
    return BACKENDS.create(backend, model, **options)
