"""A scripted model that also asks: for unit tests of the clarification loop around the LLM, never a feature's model.

Its script mixes actions and questions; the next entry is found from the context alone: the steps listed on
the last `Robot:` line plus the questions answered so far (one `Person:` line each).
"""

from __future__ import annotations

from collections.abc import Sequence

from talkdem.llm.interface.base import LanguageModel, ModelIdentity
from talkdem.llm.interface.requests import GenerateRequest, LoglikelihoodRequest


def script_position(context: str) -> int:
    """Entries of the script already used in `context` (SayCan's layout or ReAct's)."""
    if "\nTask: " in context:  # ReAct: one `Action:` per entry after the query, the last one open
        return context.rsplit("\nTask: ", 1)[-1].count("\nAction:") - 1
    return context.count("\nPerson: ") + context.rsplit("\nRobot: ", 1)[-1].count(",")


class ClarifyingLM(LanguageModel):
    def __init__(self, script: Sequence[str], *, loglikelihood: bool = True) -> None:
        self.script = list(script)
        self.identity = ModelIdentity("scripted", "clarifying-test-model", "1")
        self.supports_loglikelihood = loglikelihood
        self.contexts: list[str] = []

    def _wanted(self, context: str) -> str:
        return self.script[min(script_position(context), len(self.script) - 1)]

    def loglikelihood(self, requests: Sequence[LoglikelihoodRequest]) -> list[float]:
        self.contexts.extend(r.context for r in requests[:1])
        return [
            0.0 if r.continuation.strip() == self._wanted(r.context) else -10.0 - len(r.continuation) for r in requests
        ]

    def generate(self, requests: Sequence[GenerateRequest]) -> list[str]:
        out = []
        for request in requests:
            if request.prompt.endswith("Thought:"):
                out.append(" I should go on")
            else:
                out.append(self._wanted(request.prompt))
        return out
