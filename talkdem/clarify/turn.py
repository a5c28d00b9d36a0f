"""One episode's clarification turn: the questions offered while the budget lasts, answered by the simulated person.

The one home of the rule, for the SayCan and ReAct planners (`talkdem.planner`) and the Gymnasium env alike.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from talkdem.clarify.questions import is_question, question_texts

if TYPE_CHECKING:
    from talkdem.clarify.person import Exchange, SimulatedPerson

__all__ = ["ClarificationTurn"]


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
