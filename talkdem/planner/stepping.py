"""Episodes as step machines: a planner's episode hands out what it needs from the model and takes the answers.

An episode is a generator (`EpisodeSteps`): it yields a request (`ChoiceRequest`, `ScoreRequest`,
`GenerateRequest`), receives the answer (a `BestContinuation`, a list of scores, a text) and finally returns its
result. The planner never calls the model itself, so whoever drives the episode decides how requests reach the
model: `drive` answers them one at a time (what `plan()` does); the run scheduler (`talkdem.runs.scheduler`)
keeps many episodes in flight and hands the model all their pending requests at once, as lm-evaluation-harness
hands a backend every request of a kind.

The clarification turn (`ClarificationTurn`) lives here once for every planner: which questions are offered
while the budget lasts, and answering a chosen question by the simulated person.
"""

from __future__ import annotations

from collections.abc import Generator
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, TypeVar

from talkdem.clarify.questions import is_question, question_texts
from talkdem.llm.interface.base import LanguageModel, answer_requests
from talkdem.llm.interface.requests import ModelRequest

if TYPE_CHECKING:
    from talkdem.clarify import Exchange, SimulatedPerson

__all__ = ["ClarificationTurn", "EpisodeSteps", "drive"]

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


@dataclass
class ClarificationTurn:
    """The questions of one episode: offered while the budget lasts, answered by the simulated person.

    A question is not an action: the planner that chose one writes the exchange into its context and chooses
    again; it does not count towards the step limit (the budget bounds it instead).
    """

    person: SimulatedPerson | None
    budget: int
    dialogue: list[Exchange] = field(default_factory=list)

    def offered(self) -> tuple[str, ...]:
        """The fixed questions the planner may choose now (none without a person or once the budget is spent)."""
        if self.person is None or len(self.dialogue) >= self.budget:
            return ()
        return question_texts()

    def ask(self, choice: str, steps_taken: int) -> Exchange | None:
        """The person's answer when `choice` is an offered question (None: `choice` is an action to execute)."""
        if self.person is None or not self.offered() or not is_question(choice):
            return None
        exchange = self.person.ask(choice, steps_taken)
        self.dialogue.append(exchange)
        return exchange

    def record(self) -> tuple[Exchange, ...] | None:
        """The dialogue for the episode's result (None: not in clarification mode)."""
        return tuple(self.dialogue) if self.person is not None else None
