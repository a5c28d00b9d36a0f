"""LLM backends behind one small interface (`LanguageModel`), registered by name and imported lazily.

Importing this package loads no backend: torch, transformers, llama.cpp and vLLM are imported only when
`load_model` instantiates the backend that needs them.
"""

from talkdem.llm.base import BestContinuation, LanguageModel, ModelIdentity
from talkdem.llm.models import DEFAULT_MODEL, MODELS, ModelSpec, get_model
from talkdem.llm.registry import BACKENDS, load_model
from talkdem.llm.requests import GenerateRequest, LoglikelihoodRequest

__all__ = [
    "BACKENDS",
    "DEFAULT_MODEL",
    "MODELS",
    "BestContinuation",
    "GenerateRequest",
    "LanguageModel",
    "LoglikelihoodRequest",
    "ModelIdentity",
    "ModelSpec",
    "get_model",
    "load_model",
]
