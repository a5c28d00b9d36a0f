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

register_generator("rules", RulesGenerator)

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
