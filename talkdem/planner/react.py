"""A closed-loop ReAct planner (thought, action, observation) on the simulator seam, with any LLM backend.

At each step the model writes a short thought (greedy, cut at the first sentence end and at
`thought_tokens` tokens), then an action, which is executed; the simulator's answer in words
(`talkdem.sim.observation`, what the Gymnasium environment returns) is appended as the observation, so the
model reads every failure. The episode ends at `done` or at the step limit.

How an action becomes a skill:
- Backends with prompt log-likelihoods (llama.cpp, transformers, vLLM, a served model with its tokenizer):
  the action is the vocabulary skill with the highest summed log-probability after `Action:`, found by the
  backend's `best_continuation` (exact branch and bound over the skills' token trie). This was chosen over
  token-by-token decoding constrained to the trie because greedy constrained decoding commits to the best
  first token (` find`) and can end in a skill whose whole probability is lower; the exact argmax cannot, it
  is SayCan's own choice rule (so a ReAct and a SayCan run differ only by the thought and the feedback), and
  it reuses the fast scorers the backends already have. The action is therefore always in the vocabulary.
- Chat endpoints (no log-likelihoods): the model writes the action and it is parsed (`parse_skill`: case,
  articles and a trailing period are normalised). Text that is no skill is executed as written, so the
  simulator records it as a failed step (`instruction not supported`), and the model sees that.
The thoughts are kept per step (`PlanResult.generated`) and stored in the run's traces.

Clarification (`clarify` oracle or in-pattern): a sentence after the header names the fixed questions; while
the budget lasts they are scored with the skills (or, for chat endpoints, a written action starting with `ask`
is a question, matched to a slot by `talkdem.clarify.match_question`). A question is answered on a `Person:`
line instead of an observation, and is not a step of the episode (it does not count towards `max_steps`);
the thought before it stays in the context but is not kept with the actions' thoughts.
"""

from __future__ import annotations

import hashlib
import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Literal, cast

from talkdem.clarify.questions import is_question, question_texts
from talkdem.clarify.turn import ClarificationTurn
from talkdem.llm.interface.base import BestContinuation, LanguageModel
from talkdem.llm.interface.requests import ChoiceRequest, GenerateRequest
from talkdem.planner.examples import task_type_examples
from talkdem.planner.prompt import Demonstration
from talkdem.planner.saycan import PlanResult, check_clarify
from talkdem.planner.stepping import EpisodeSteps, drive
from talkdem.planner.strategies import PlannerInput
from talkdem.seeds.records import SeedTask
from talkdem.sim.observation import observation_of
from talkdem.sim.seam import DEFAULT_MAX_STEPS, SimulatorBackend, load_simulator
from talkdem.skills import vocabulary

if TYPE_CHECKING:
    from talkdem.clarify import SimulatedPerson

__all__ = ["REACT_HEADER", "ReActConfig", "ReActPlanner", "react_prompt_version"]

REACT_HEADER = (
    "You are a household robot. You solve a task one action at a time. Before each action, think in one "
    "short sentence. Each action is one skill: find a/an OBJECT, pick up the OBJECT, put down the OBJECT, "
    "open the OBJECT, close the OBJECT, slice the OBJECT, turn on the OBJECT, turn off the OBJECT, or done "
    "when the task is complete. After each action you see what happened; if it failed, try something else.\n\n"
)
_SENTENCE_END = (".", "!", "?", "\n")


def react_clarify_line(budget: int) -> str:
    """The sentence after the header in clarification mode."""
    return (
        f"If the task is unclear, you may first ask the person at most {budget} question(s) as an action, one "
        f"at a time: {'; '.join(question_texts())}. The person's answer follows on a Person: line.\n\n"
    )


def react_prompt_version(clarify: str = "none", budget: int = 0) -> str:
    """Names the prompt text (the header and the demonstrations' layout, and in clarification mode the
    questions' sentence): changes when any of them changes."""
    layout = REACT_HEADER + _demo_thought("find a mug") + _demo_thought("done")
    if clarify != "none":
        layout += react_clarify_line(budget)
    return "react-" + hashlib.sha256(layout.encode()).hexdigest()[:8]


@dataclass(frozen=True)
class ReActConfig:
    max_steps: int = DEFAULT_MAX_STEPS
    thought_tokens: int = 24
    """The budget of one thought (it also ends at the first sentence end)."""
    action_tokens: int = 16
    """Chat endpoints: the budget of one written action."""
    simulator: str = "symbolic"
    clarify: Literal["none", "oracle", "in-pattern"] = "none"
    """Who answers the planner's questions (`talkdem.clarify`); `none`: no questions are offered."""
    clarify_budget: int = 0
    """Questions allowed per episode (0 without clarification)."""

    def __post_init__(self) -> None:
        check_clarify(self.clarify, self.clarify_budget)

    @property
    def planner_name(self) -> str:
        return "react"


def _demo_thought(skill: str) -> str:
    # Demonstrations are reference plans (every step succeeds), so their thoughts can only announce the step.
    if skill == "done":
        return "The task is complete."
    return f"Next I should {skill}."


def _render_demo(demo: Demonstration) -> str:
    from talkdem.sim.trace import StepRecord

    lines = [f"Task: {demo.instruction}"]
    if demo.interpretation:
        lines.append(f"Thought: {' '.join(demo.interpretation.split())}")
    for index, skill in enumerate(demo.plan):
        success = StepRecord(index, skill, skill, True, "", None, None, None, None)
        lines += [f"Thought: {_demo_thought(skill)}", f"Action: {skill}", f"Observation: {observation_of(success)}"]
    return "\n".join(lines) + "\n\n"


class ReActPlanner:
    """`plan(task, planner_input) -> PlanResult`, like `SayCanPlanner`, so the runner can drive either."""

    def __init__(
        self,
        model: LanguageModel,
        config: ReActConfig | None = None,
        examples: Sequence[Demonstration] | None = None,
        simulator: SimulatorBackend | None = None,
    ) -> None:
        self.model = model
        self.config = config or ReActConfig()
        self.examples = tuple(examples if examples is not None else task_type_examples())
        self.skills = [skill.text for skill in vocabulary()]
        self.simulator = simulator or load_simulator(self.config.simulator)

    def prompt_for(self, planner_input: PlannerInput) -> str:
        clarify = react_clarify_line(self.config.clarify_budget) if self.config.clarify != "none" else ""
        parts = [REACT_HEADER, clarify, planner_input.preamble]
        parts += [_render_demo(example) for example in self.examples]
        if planner_input.demonstrations:
            parts.append(planner_input.demonstrations_intro)
            parts += [_render_demo(demo) for demo in planner_input.demonstrations]
        query = f"Task: {' '.join(planner_input.instruction.split())}\n"
        if planner_input.interpretation:
            query += f"Thought: {' '.join(planner_input.interpretation.split())}\n"
        parts.append(query)
        return "".join(parts)

    def _thought(self, context: str) -> EpisodeSteps[str]:
        request = GenerateRequest(context + "Thought:", max_new_tokens=self.config.thought_tokens, stop=_SENTENCE_END)
        text = " ".join(cast(str, (yield request)).split())
        return text.rstrip(".!?") + "." if text else "(no thought)."

    def _action(self, context: str, questions: Sequence[str] = ()) -> EpisodeSteps[tuple[str, float, str]]:
        """(the skill string to execute or the question to ask, its score, the raw text written: chat
        endpoints only)."""
        if self.model.supports_loglikelihood:
            candidates = [*self.skills, *questions]
            found = cast(BestContinuation, (yield ChoiceRequest(context, tuple(" " + s for s in candidates))))
            return candidates[found.index], found.score, ""
        from talkdem.sim.parser import canonical_text, parse_skill

        raw = cast(str, (yield GenerateRequest(context + " ", max_new_tokens=self.config.action_tokens)))
        written = " ".join(raw.split())
        if questions and is_question(written):
            return written, 0.0, raw
        skill = parse_skill(written)
        # An unparseable action is executed as written: the simulator fails it (`instruction not supported`).
        return (canonical_text(skill) if skill is not None else written), 0.0, raw

    def plan(self, task: SeedTask, planner_input: PlannerInput, person: SimulatedPerson | None = None) -> PlanResult:
        """Plan and execute one episode; `person` answers questions (required in clarification mode)."""
        return drive(self.episode(task, planner_input, person), self.model)

    def episode(
        self, task: SeedTask, planner_input: PlannerInput, person: SimulatedPerson | None = None
    ) -> EpisodeSteps[PlanResult]:
        """`plan` as a step machine (`talkdem.planner.stepping`): yields what it needs from the model."""
        if (self.config.clarify != "none") != (person is not None):
            raise ValueError(f"clarify {self.config.clarify!r}: a simulated person is needed exactly in that mode")
        turn = ClarificationTurn(person, self.config.clarify_budget)
        start = time.perf_counter()
        prompt = self.prompt_for(planner_input)
        context = prompt
        plan: list[str] = []
        scores: list[float] = []
        thoughts: list[str] = []
        episode = self.simulator.start(task, max_steps=self.config.max_steps)
        while not episode.over:
            thought = yield from self._thought(context)
            context += f"Thought: {thought}\nAction:"
            skill, score, _raw = yield from self._action(context, turn.offered())
            exchange = turn.ask(skill, len(plan))
            if exchange is not None:
                context += f" {exchange.question}\nPerson: {exchange.answer}\n"
                continue
            record = episode.step(skill)
            plan.append(skill)
            scores.append(score)
            thoughts.append(thought)
            context += f" {skill}\nObservation: {observation_of(record)}\n"
        return PlanResult(
            prompt=prompt,
            plan=tuple(plan),
            step_scores=tuple(scores),
            trace=episode.finish(),
            planning_seconds=time.perf_counter() - start,
            generated=tuple(thoughts),
            dialogue=turn.record(),
        )
