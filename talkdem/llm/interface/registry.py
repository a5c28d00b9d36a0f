"""Backends registered by name as `module:Class`, imported only when asked for."""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

from talkdem.llm.interface.base import LanguageModel
from talkdem.llm.interface.options import BackendOption, OptionValue, parse_model_args
from talkdem.registry import Registry

__all__ = [
    "BACKENDS",
    "DEFAULT_BACKEND",
    "LOCAL_BACKENDS",
    "backend_options",
    "load_model",
    "model_args",
]

BACKENDS: Registry[LanguageModel] = Registry("backend")
BACKENDS.register("hf", "talkdem.llm.backends.hf:HFCausalLM", "Hugging Face transformers")
BACKENDS.register("llamacpp", "talkdem.llm.backends.llamacpp:LlamaCppLM", "llama.cpp")
BACKENDS.register("vllm", "talkdem.llm.backends.vllm_backend:VLLMLM", "vLLM")
BACKENDS.register("openai", "talkdem.llm.backends.openai_compat:OpenAICompatibleLM", "OpenAI-compatible server")

DEFAULT_BACKEND = "llamacpp"
"""The backend a run, a sweep's model and the demo use when none is named (the default model is a GGUF)."""
LOCAL_BACKENDS = ("hf", "llamacpp")
"""Backends that compute in the caller's own process on its CPUs (`threads` applies; a sweep's worker gets its
share of them)."""


def load_model(backend: str, model: str, **options: Any) -> LanguageModel:
    """Instantiate backend `backend` on `model` (a path, model id or served name)."""
    return BACKENDS.create(backend, model, **options)


def backend_options(backend: str) -> tuple[BackendOption, ...]:
    """The options `backend` declares (its class's module is imported; the heavy libraries are not, a backend
    imports those when it is constructed)."""
    factory = BACKENDS.factory(backend)
    declared: tuple[BackendOption, ...] = getattr(factory, "options", ())
    return declared


def model_args(backend: str, items: Iterable[str]) -> dict[str, OptionValue]:
    """`KEY=VALUE` strings as `backend`'s typed constructor options; ValueError naming the option otherwise."""
    return parse_model_args(backend, backend_options(backend), items)
