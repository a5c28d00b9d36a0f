"""A scripted language model for unit tests of the code around the LLM (planner loop, runner, resume).

It prefers, at each step, the next skill of a fixed script; it is never used as a feature's model.
"""

from __future__ import annotations

from collections.abc import Sequence

from talkdem.llm.interface.base import LanguageModel, ModelIdentity
from talkdem.llm.interface.requests import GenerateRequest, LoglikelihoodRequest


class ScriptedLM(LanguageModel):
    def __init__(self, script: Sequence[str], generated: str = "put the apple in the fridge") -> None:
        self.script = list(script)
        self.generated = generated
        self.identity = ModelIdentity("scripted", "scripted-test-model", "1")
        self.calls = 0

    def _wanted(self, context: str) -> str:
        # Steps taken so far = commas after the query's "Robot: 1." (each appended step adds ", <n>.").
        steps_taken = context.rsplit("Robot: 1.", 1)[-1].count(",")
        return self.script[min(steps_taken, len(self.script) - 1)]

    def loglikelihood(self, requests: Sequence[LoglikelihoodRequest]) -> list[float]:
        self.calls += 1
        return [
            0.0 if r.continuation.strip() == self._wanted(r.context) else -10.0 - len(r.continuation) for r in requests
        ]

    def generate(self, requests: Sequence[GenerateRequest]) -> list[str]:
        return [self.generated for _ in requests]
