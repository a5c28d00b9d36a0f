"""Instruction generators behind one interface: `rules` (embedded default) and `llm` (prompted backends)."""

from builders.generation.base import (
    CLEAN,
    GenerationRequest,
    Generator,
    derive_seed,
    get_generator,
    register_generator,
    registered_generators,
)
from builders.generation.rules import RulesGenerator


def _default_llm_generator() -> Generator:
    """The paper's prompts on the embedded default model (SmolLM2-135M through transformers)."""
    from builders.generation.llm import LLMGenerator
    from talkdem.llm.registry import load_model

    return LLMGenerator(load_model("hf", "smollm2-135m-instruct"))


register_generator("rules", RulesGenerator)
register_generator("llm", _default_llm_generator)

__all__ = [
    "CLEAN",
    "GenerationRequest",
    "Generator",
    "RulesGenerator",
    "derive_seed",
    "get_generator",
    "register_generator",
    "registered_generators",
]
