"""Requests to a language model as plain data, so a backend can sort, batch and cache them."""

from __future__ import annotations

from dataclasses import dataclass, field

__all__ = ["GenerateRequest", "LoglikelihoodRequest"]


@dataclass(frozen=True)
class LoglikelihoodRequest:
    """log p(continuation | context), summed over the continuation's tokens.

    Tokenization is central and fixed: the context and the continuation are tokenized separately and
    concatenated, so put the separating space at the start of the continuation (`" find an apple"`).
    """

    context: str
    continuation: str


@dataclass(frozen=True)
class GenerateRequest:
    """Generation from a prompt: greedy by default (deterministic decoding).

    A `temperature` above 0 samples, seeded by `seed`, so that a caller can ask for a different output
    reproducibly (the dataset builder's regeneration of a variant that failed verification).
    """

    prompt: str
    max_new_tokens: int = 64
    stop: tuple[str, ...] = field(default=("\n",))
    """Generation is cut at the first of these strings (which is not returned)."""
    temperature: float = 0.0
    seed: int = 0
    chat: bool = True
    """Wrap the prompt in the model's chat template when the backend uses one; False: a plain completion
    of the prompt text (REI-Bench's CoT and TOCC generate this way, continuing the prompt as written)."""

    def __post_init__(self) -> None:
        if self.temperature < 0:
            raise ValueError(f"temperature must be >= 0, got {self.temperature}")
