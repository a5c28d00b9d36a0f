"""A closed-loop ReAct planner (thought, action, observation) on the simulator seam, with any LLM backend.

At each step the model writes a short thought (greedy, cut at the first sentence end and at
`thought_tokens` tokens), then an action, which is executed; the simulator's answer in words
(`talkdem.env.observation_of`, what the Gymnasium environment returns) is appended as the observation, so the
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
"""

from __future__ import annotations

import hashlib
import time
from collections.abc import Sequence
from dataclasses import dataclass

from talkdem.llm.base import LanguageModel
from talkdem.llm.requests import GenerateRequest
from talkdem.planner.examples import task_type_examples
from talkdem.planner.prompt import Demonstration
from talkdem.planner.saycan import PlanResult
from talkdem.planner.strategies import PlannerInput
from talkdem.seeds.records import SeedTask
from talkdem.sim.seam import DEFAULT_MAX_STEPS, SimulatorBackend, load_simulator
from talkdem.skills import vocabulary

__all__ = ["REACT_HEADER", "ReActConfig", "ReActPlanner", "react_prompt_version"]

REACT_HEADER = (
    "You are a household robot. You solve a task one action at a time. Before each action, think in one "
    "short sentence. Each action is one skill: find a/an OBJECT, pick up the OBJECT, put down the OBJECT, "
    "open the OBJECT, close the OBJECT, slice the OBJECT, turn on the OBJECT, turn off the OBJECT, or done "
    "when the task is complete. After each action you see what happened; if it failed, try something else.\n\n"
)
_SENTENCE_END = (".", "!", "?", "\n")


def react_prompt_version() -> str:
    """Names the prompt text (the header and the demonstrations' layout): changes when either changes."""
    layout = REACT_HEADER + _demo_thought("find a mug") + _demo_thought("done")
    return "react-" + hashlib.sha256(layout.encode()).hexdigest()[:8]


@dataclass(frozen=True)
class ReActConfig:
    max_steps: int = DEFAULT_MAX_STEPS
    thought_tokens: int = 24
    """The budget of one thought (it also ends at the first sentence end)."""
    action_tokens: int = 16
    """Chat endpoints: the budget of one written action."""
    simulator: str = "symbolic"

    @property
    def planner_name(self) -> str:
        return "react"


def _demo_thought(skill: str) -> str:
    # Demonstrations are reference plans (every step succeeds), so their thoughts can only announce the step.
    if skill == "done":
        return "The task is complete."
    return f"Next I should {skill}."


def _render_demo(demo: Demonstration) -> str:
    from talkdem.env.feedback import observation_of
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
        parts = [REACT_HEADER, planner_input.preamble]
        parts += [_render_demo(example) for example in self.examples]
        if planner_input.demonstrations:
            parts.append(planner_input.demonstrations_intro)
            parts += [_render_demo(demo) for demo in planner_input.demonstrations]
        query = f"Task: {' '.join(planner_input.instruction.split())}\n"
        if planner_input.interpretation:
            query += f"Thought: {' '.join(planner_input.interpretation.split())}\n"
        parts.append(query)
        return "".join(parts)

    def _thought(self, context: str) -> str:
        request = GenerateRequest(context + "Thought:", max_new_tokens=self.config.thought_tokens, stop=_SENTENCE_END)
        text = " ".join(self.model.generate([request])[0].split())
        return text.rstrip(".!?") + "." if text else "(no thought)."

    def _action(self, context: str) -> tuple[str, float, str]:
        """(the skill string to execute, its score, the raw text written: chat endpoints only)."""
        if self.model.supports_loglikelihood:
            found = self.model.best_continuation(context, [" " + s for s in self.skills])
            return self.skills[found.index], found.score, ""
        from talkdem.sim.parser import canonical_text, parse_skill

        raw = self.model.generate([GenerateRequest(context + " ", max_new_tokens=self.config.action_tokens)])[0]
        written = " ".join(raw.split())
        skill = parse_skill(written)
        # An unparseable action is executed as written: the simulator fails it (`instruction not supported`).
        return (canonical_text(skill) if skill is not None else written), 0.0, raw

    def plan(self, task: SeedTask, planner_input: PlannerInput) -> PlanResult:
        from talkdem.env.feedback import observation_of

        start = time.perf_counter()
        prompt = self.prompt_for(planner_input)
        context = prompt
        plan: list[str] = []
        scores: list[float] = []
        thoughts: list[str] = []
        episode = self.simulator.start(task, max_steps=self.config.max_steps)
        while not episode.over:
            thought = self._thought(context)
            context += f"Thought: {thought}\nAction:"
            skill, score, _raw = self._action(context)
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
        )
