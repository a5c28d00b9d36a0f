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
    """Greedy generation from a prompt (deterministic decoding)."""

    prompt: str
    max_new_tokens: int = 64
    stop: tuple[str, ...] = field(default=("\n",))
    """Generation is cut at the first of these strings (which is not returned)."""
