"""LLM backends behind one small interface (`LanguageModel`), registered by name and imported lazily.

Three subpackages: `interface` (the interface, requests, backend options, the registry, the model catalogue),
`backends` (hf, llamacpp, vllm, openai and their shared tokenizing) and `scoring` (token trie, branch and bound,
prefix-cached and served scoring, the result cache). Importing this package loads no backend: torch,
transformers, llama.cpp and vLLM are imported only when `load_model` instantiates the backend that needs them.
"""

from talkdem.llm.interface.base import BestContinuation, LanguageModel, ModelIdentity
from talkdem.llm.interface.models import DEFAULT_MODEL, MODELS, ModelSpec, get_model
from talkdem.llm.interface.options import BackendOption
from talkdem.llm.interface.registry import BACKENDS, backend_options, load_model, model_args
from talkdem.llm.interface.requests import GenerateRequest, LoglikelihoodRequest

__all__ = [
    "BACKENDS",
    "DEFAULT_MODEL",
    "MODELS",
    "BackendOption",
    "BestContinuation",
    "GenerateRequest",
    "LanguageModel",
    "LoglikelihoodRequest",
    "ModelIdentity",
    "ModelSpec",
    "backend_options",
    "get_model",
    "load_model",
    "model_args",
]
