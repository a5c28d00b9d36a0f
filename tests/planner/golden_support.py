"""Shared pieces of the golden prompt tests: one fixed episode, a recording scripted model, and a
bag-of-words encoder standing in for MiniLM (the golden files test rendering, not retrieval quality)."""

from __future__ import annotations

import hashlib
import re
from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray
from scripted_lm import ScriptedLM

from talkdem.llm.interface.requests import GenerateRequest
from talkdem.runs.sampling import select_episodes
from talkdem.schema import parse_conditions

# The first task of the stratified order at referential imprecision, level 3: a short, irregular instruction.
EPISODE = select_episodes(parse_conditions("referential_imprecision:3"), 1)[0]
ANSWER = "Put a clean mug in the coffee machine."


class RecordingLM(ScriptedLM):
    """Answers every generation with a fixed sentence (and a ".", which REI-Bench's stop rule removes)."""

    def __init__(self, generated: str = ANSWER) -> None:
        super().__init__(["done"], generated=generated)
        self.prompts: list[GenerateRequest] = []

    def generate(self, requests: Sequence[GenerateRequest]) -> list[str]:
        self.prompts += requests
        return [self.generated.split(".")[0] for _ in requests]  # the backends cut at the stop string


def bag_of_words(texts: Sequence[str]) -> NDArray[np.float64]:
    """Unit vectors of hashed lower-cased words: texts sharing words are similar. Deterministic."""
    rows = np.zeros((len(texts), 512))
    for row, text in enumerate(texts):
        for word in re.findall(r"[a-z]+", text.lower()):
            rows[row, int(hashlib.sha256(word.encode()).hexdigest(), 16) % 512] += 1.0
    norms = np.linalg.norm(rows, axis=1, keepdims=True)
    return np.asarray(rows / np.where(norms == 0, 1.0, norms), dtype=np.float64)
