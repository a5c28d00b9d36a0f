"""Episodes as step machines: a planner's episode hands out what it needs from the model and takes the answers.

An episode is a generator (`EpisodeSteps`): it yields a request (`ChoiceRequest`, `ScoreRequest`,
`GenerateRequest`), receives the answer (a `BestContinuation`, a list of scores, a text) and finally returns its
result. The planner never calls the model itself, so whoever drives the episode decides how requests reach the
model: `drive` answers them one at a time (what `plan()` does); the run scheduler (`talkdem.runs.scheduler`)
keeps many episodes in flight and hands the model all their pending requests at once, as lm-evaluation-harness
hands a backend every request of a kind.

Every planner takes its clarification turn through `talkdem.clarify.ClarificationTurn`, as the Gymnasium env does.
"""

from __future__ import annotations

from collections.abc import Generator
from typing import TypeVar

from talkdem.llm.interface.base import LanguageModel, answer_requests
from talkdem.llm.interface.requests import ModelRequest

__all__ = ["EpisodeSteps", "drive"]

Result = TypeVar("Result")

EpisodeSteps = Generator[ModelRequest, object, Result]
"""An episode in flight: yields requests, is sent their answers, returns its result."""


def drive(steps: EpisodeSteps[Result], model: LanguageModel) -> Result:
    """Run an episode to its end, answering each request as it comes (one episode, nothing in flight beside it)."""
    try:
        request = next(steps)
        while True:
            (answer,) = answer_requests(model, [request])
            request = steps.send(answer)
    except StopIteration as finished:
        result: Result = finished.value
        return result
