"""Requests to a language model as plain data, so a backend can sort, batch and cache them."""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from typing import Any

__all__ = ["ChoiceRequest", "GenerateRequest", "LoglikelihoodRequest", "ModelRequest", "ScoreRequest"]


@dataclass(frozen=True)
class LoglikelihoodRequest:
    """log p(continuation | context), summed over the continuation's tokens.

    Tokenization is central and fixed: the context and the continuation are tokenized separately and
    concatenated, so put the separating space at the start of the continuation (`" find an apple"`).
    """

    context: str
    continuation: str


@dataclass(frozen=True)
class ChoiceRequest:
    """The continuation with the highest summed log-probability after `context` (one SayCan or ReAct step
    under sum scoring); answered with a `BestContinuation`. Ties go to the earlier continuation.

    `session` names the episode in flight that asks (the scheduler's slot): a backend that keeps state per
    episode (the multi-sequence llama.cpp scorer keeps each episode's context in its own sequence) uses it; it
    is not part of the request's value (equality, hashing, caching), since it changes no answer.
    """

    context: str
    continuations: tuple[str, ...]
    session: int = field(default=0, compare=False)


@dataclass(frozen=True)
class ScoreRequest:
    """Every continuation's summed log-probability after `context` (mean scoring, `--log-top`); answered
    with a list of floats in the continuations' order. `session` as in `ChoiceRequest`."""

    context: str
    continuations: tuple[str, ...]
    session: int = field(default=0, compare=False)


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
    system: str = ""
    """A system message sent before the prompt (the user message) when the chat template is used; a plain
    completion gets it as the prompt's first paragraph (`completion_text`). Empty: no system message."""
    json_schema: str = ""
    """A JSON schema (as JSON text, so the request stays hashable) the output must follow, on backends that can
    constrain decoding to it (`LanguageModel.supports_json_schema`); the others ignore it. Empty: free text."""

    def __post_init__(self) -> None:
        if self.temperature < 0:
            raise ValueError(f"temperature must be >= 0, got {self.temperature}")
        if self.json_schema:
            try:
                schema = json.loads(self.json_schema)
            except json.JSONDecodeError as error:
                raise ValueError(f"json_schema is not JSON text: {error}") from None
            if not isinstance(schema, dict):
                raise ValueError("json_schema must be a JSON object (a schema)")

    def messages(self) -> list[dict[str, str]]:
        """The chat messages: the system message (when there is one), then the prompt as the user's."""
        system = [{"role": "system", "content": self.system}] if self.system else []
        return [*system, {"role": "user", "content": self.prompt}]

    def completion_text(self) -> str:
        """The text a plain completion continues: the system message as a first paragraph, then the prompt."""
        return f"{self.system}\n\n{self.prompt}" if self.system else self.prompt

    def schema(self) -> dict[str, Any] | None:
        """The parsed JSON schema, or None for free text."""
        if not self.json_schema:
            return None
        parsed: dict[str, Any] = json.loads(self.json_schema)
        return parsed


ModelRequest = ChoiceRequest | ScoreRequest | GenerateRequest
"""What a planner's episode asks of the model at one step (`talkdem.planner.stepping`)."""
