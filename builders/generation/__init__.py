"""Instruction generators behind one interface: `rules` (embedded default, `rules-v3`; `rules-v2` by name) and
`llm` (prompted backends)."""

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
from builders.generation.rules_v3 import RulesV3Generator


def _default_llm_generator() -> Generator:
    """The paper's prompts on the embedded default model (SmolLM2-135M through transformers)."""
    from builders.generation.llm import LLMGenerator
    from talkdem.llm.interface.registry import load_model

    return LLMGenerator(load_model("hf", "smollm2-135m-instruct"))


register_generator("rules", RulesV3Generator)  # the default: rules-v3
register_generator("rules-v3", RulesV3Generator)
register_generator("rules-v2", RulesGenerator)  # the phrase banks of the data before issue 19, byte for byte
register_generator("llm", _default_llm_generator)

__all__ = [
    "CLEAN",
    "GenerationRequest",
    "Generator",
    "RulesGenerator",
    "RulesV3Generator",
    "derive_seed",
    "get_generator",
    "register_generator",
    "registered_generators",
]
