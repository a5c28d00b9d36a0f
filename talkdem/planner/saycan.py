"""SayCan planning in the simulator: at each step every vocabulary skill is scored by the LLM and the best
one is executed.

Decisions (the paper follows LoTa-Bench / REI-Bench's SayCan setup, which scores skills by log-likelihood
and executes them in the simulator):
- Scoring: the sum of the skill's token log-probabilities (default) or their mean (`scoring="mean"`).
  Under sum scoring a backend that offers `best_continuation` (llama.cpp, transformers) finds the winner
  exactly by branch and bound over the skills' token trie, without scoring every skill in full; mean
  scoring, and `log_top` (which logs the best skills of every step), score every skill.
- Simulator feedback after a failed skill (`feedback`, docs/strategies.md): `message` (the default, as
  REI-Bench's config runs it, `use_predefined_prompt: True`): the step is written with the simulator's
  message, ` <skill> (this action failed: <message>), <n>.`; `mask`: the skill that just failed is not
  offered again until a step succeeds (an affordance stand-in of ours, no source does it); `both`; `none`
  (LoTa-Bench's default): failures are not used at all. Two fields carry it, `mask_failed` and
  `failure_message`, so that a config keeps one field per mechanism.
- The episode ends at `done` or after `max_steps` steps (30, as REI-Bench).
- Generative mode (for chat endpoints without prompt log-likelihoods): the model writes the next step and
  it is mapped to the most similar vocabulary skill; results are labelled `saycan-generative`.
- Clarification (`clarify` oracle or in-pattern, `talkdem.clarify`): the fixed questions are scored with the
  skills while the episode's budget (`clarify_budget`) lasts; generative mode asks when the written step starts
  with `ask`. A question is not an action: it is answered by the simulated person, shown as dialogue
  (`append_exchange`), and does not count towards `max_steps` (the budget bounds it instead: an episode has at
  most `max_steps` actions and `clarify_budget` questions).
"""

from __future__ import annotations

import difflib
import logging
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Literal, cast

from talkdem.clarify.questions import is_question, question_texts
from talkdem.clarify.turn import ClarificationTurn
from talkdem.llm.interface.base import BestContinuation, LanguageModel
from talkdem.llm.interface.requests import ChoiceRequest, GenerateRequest, ScoreRequest
from talkdem.planner.examples import task_type_examples
from talkdem.planner.prompt import Demonstration, append_exchange, append_step, build_prompt, clarify_intro
from talkdem.planner.stepping import EpisodeSteps, drive
from talkdem.planner.strategies import PlannerInput
from talkdem.seeds.records import SeedTask
from talkdem.sim.seam import DEFAULT_MAX_STEPS, SimulatorBackend, load_simulator
from talkdem.sim.trace import EpisodeTrace
from talkdem.skills import vocabulary

if TYPE_CHECKING:
    from talkdem.clarify import Exchange, SimulatedPerson

__all__ = ["FEEDBACK", "Feedback", "PlanResult", "SayCanConfig", "SayCanPlanner", "check_clarify", "nearest_skill"]

_log = logging.getLogger(__name__)


Feedback = Literal["mask", "message", "both", "none"]
FEEDBACK: dict[Feedback, tuple[bool, bool]] = {
    "mask": (True, False),
    "message": (False, True),
    "both": (True, True),
    "none": (False, False),
}
"""Feedback policy -> (mask_failed, failure_message)."""


def check_clarify(clarify: str, budget: int) -> None:
    """A clarification setting a planner can run: a known mode, a budget only with one (and at least 1)."""
    if clarify not in ("none", "oracle", "in-pattern"):
        raise ValueError(f"clarify must be one of none, oracle, in-pattern, got {clarify!r}")
    if clarify == "none" and budget:
        raise ValueError("a question budget needs clarification (--clarify oracle or in-pattern)")
    if clarify != "none" and budget < 1:
        raise ValueError(f"with --clarify {clarify} the question budget must be at least 1, got {budget}")


@dataclass(frozen=True)
class SayCanConfig:
    max_steps: int = DEFAULT_MAX_STEPS
    scoring: Literal["sum", "mean"] = "sum"
    mask_failed: bool = False
    """Do not offer a skill again right after it failed (until a step succeeds)."""
    mode: Literal["scoring", "generative"] = "scoring"
    log_top: int = 0
    """When > 0, score every skill at every step and log (and keep in the result) the best `log_top`."""
    failure_message: bool = True
    """Write a failed step with the simulator's message, as REI-Bench does."""
    clarify: Literal["none", "oracle", "in-pattern"] = "none"
    """Who answers the planner's questions (`talkdem.clarify`); `none`: no questions are offered."""
    clarify_budget: int = 0
    """Questions allowed per episode (0 without clarification; `talkdem run --clarify-budget`, default 2)."""

    def __post_init__(self) -> None:
        check_clarify(self.clarify, self.clarify_budget)

    @classmethod
    def with_feedback(cls, feedback: str, **fields: Any) -> SayCanConfig:
        """A config with the feedback policy `feedback` (one of FEEDBACK) and other fields as given."""
        if feedback not in FEEDBACK:
            raise ValueError(f"feedback must be one of {', '.join(FEEDBACK)}, got {feedback!r}")
        mask, message = FEEDBACK[feedback]
        return cls(**{**fields, "mask_failed": mask, "failure_message": message})

    @property
    def feedback(self) -> Feedback:
        return next(name for name, flags in FEEDBACK.items() if flags == (self.mask_failed, self.failure_message))

    @property
    def planner_name(self) -> str:
        return "saycan" if self.mode == "scoring" else "saycan-generative"


@dataclass(frozen=True)
class PlanResult:
    """One planned and executed episode."""

    prompt: str
    plan: tuple[str, ...]
    step_scores: tuple[float, ...]
    """The winning candidate's score at each step (generative mode: the mapping similarity)."""
    trace: EpisodeTrace
    planning_seconds: float
    generated: tuple[str, ...] = field(default=())
    """Generative mode: the raw text written at each step."""
    top_candidates: tuple[tuple[tuple[str, float], ...], ...] = field(default=())
    """With `log_top`: the best skills and their scores at each step."""
    dialogue: tuple[Exchange, ...] | None = None
    """Clarification mode: the questions asked and their answers, in order (None: not in that mode)."""


def nearest_skill(text: str, skills: Sequence[str]) -> tuple[str, float]:
    """The vocabulary skill most similar to free text (difflib ratio on lower-cased, trimmed text)."""
    cleaned = " ".join(text.lower().strip().strip(".,;").split())
    best, best_ratio = skills[0], -1.0
    for skill in skills:
        ratio = difflib.SequenceMatcher(None, cleaned, skill.lower()).ratio()
        if ratio > best_ratio:
            best, best_ratio = skill, ratio
    return best, best_ratio


class SayCanPlanner:
    def __init__(
        self,
        model: LanguageModel,
        config: SayCanConfig | None = None,
        examples: Sequence[Demonstration] | None = None,
        simulator: SimulatorBackend | None = None,
    ) -> None:
        self.model = model
        self.config = config or SayCanConfig()
        self.examples = tuple(examples if examples is not None else task_type_examples())
        self.skills = [skill.text for skill in vocabulary()]
        self.simulator = simulator or load_simulator("symbolic")
        if self.config.mode == "scoring" and not model.supports_loglikelihood:
            raise ValueError(
                f"{model.identity.key()} gives no prompt log-likelihoods (a chat endpoint): "
                "use the generative planner (mode='generative', `talkdem run --planner generative`)"
            )

    def prompt_for(self, planner_input: PlannerInput) -> str:
        intro = ""
        if self.config.clarify != "none":
            intro = clarify_intro(question_texts(), self.config.clarify_budget)
        return build_prompt(
            planner_input.instruction,
            self.examples,
            preamble=intro + planner_input.preamble,
            demonstrations=planner_input.demonstrations,
            demonstrations_intro=planner_input.demonstrations_intro,
            interpretation=planner_input.interpretation,
            query_label=planner_input.query_label,
        )

    def _scores(self, context: str, candidates: Sequence[str]) -> EpisodeSteps[list[float]]:
        continuations = tuple(" " + c for c in candidates)
        scores = cast("list[float]", (yield ScoreRequest(context, continuations)))
        if self.config.scoring == "mean":
            lengths = [self.model.token_count(c) for c in continuations]
            scores = [s / max(n, 1) for s, n in zip(scores, lengths, strict=True)]
        return scores

    def _choose(
        self, context: str, blocked: set[str], questions: Sequence[str], top: list[tuple[tuple[str, float], ...]]
    ) -> EpisodeSteps[tuple[str, float, str]]:
        """(the chosen skill or question, its score, the text written: generative mode only); with `log_top`,
        the step's best candidates are appended to `top`."""
        candidates = [s for s in self.skills if s not in blocked]
        if self.config.mode == "generative":
            request = GenerateRequest(context + " ", max_new_tokens=16, stop=(",", "\n"))
            text = cast(str, (yield request))
            if questions and is_question(text):
                return " ".join(text.split()), 1.0, text
            skill, similarity = nearest_skill(text, candidates)
            return skill, similarity, text
        candidates += questions
        if self.config.scoring == "sum" and not self.config.log_top:
            # Exact: the same skill as full scoring (backends with branch and bound score far fewer tokens).
            found = cast(BestContinuation, (yield ChoiceRequest(context, tuple(" " + c for c in candidates))))
            return candidates[found.index], found.score, ""
        scores = yield from self._scores(context, candidates)
        best = max(range(len(candidates)), key=lambda i: (scores[i], -i))  # ties: the earlier skill
        if self.config.log_top:
            ranked = sorted(range(len(candidates)), key=lambda i: (-scores[i], i))[: self.config.log_top]
            top.append(tuple((candidates[i], scores[i]) for i in ranked))
            _log.info("step %d: %s", len(top), ", ".join(f"{candidates[i]} {scores[i]:.3f}" for i in ranked))
        return candidates[best], scores[best], ""

    def plan(self, task: SeedTask, planner_input: PlannerInput, person: SimulatedPerson | None = None) -> PlanResult:
        """Plan and execute one episode; `person` answers questions (required in clarification mode)."""
        return drive(self.episode(task, planner_input, person), self.model)

    def episode(
        self, task: SeedTask, planner_input: PlannerInput, person: SimulatedPerson | None = None
    ) -> EpisodeSteps[PlanResult]:
        """`plan` as a step machine (`talkdem.planner.stepping`): yields what it needs from the model."""
        if (self.config.clarify != "none") != (person is not None):
            raise ValueError(f"clarify {self.config.clarify!r}: a simulated person is needed exactly in that mode")
        start = time.perf_counter()
        prompt = self.prompt_for(planner_input)
        context = prompt
        plan: list[str] = []
        step_scores: list[float] = []
        generated: list[str] = []
        top: list[tuple[tuple[str, float], ...]] = []
        blocked: set[str] = set()
        turn = ClarificationTurn(person, self.config.clarify_budget)
        # The episode steps along with the planner: each skill is executed once, as it is chosen.
        episode = self.simulator.start(task, max_steps=self.config.max_steps)
        while not episode.over:
            skill, score, text = yield from self._choose(context, blocked, turn.offered(), top)
            exchange = turn.ask(skill, len(plan))
            if exchange is not None:
                context = append_exchange(context, exchange.question, exchange.answer)
                continue
            plan.append(skill)
            step_scores.append(score)
            generated.append(text)
            outcome = episode.step(skill)
            if outcome.ok:
                blocked.clear()
            elif self.config.mask_failed:
                blocked.add(skill)
            shown = outcome.message if self.config.failure_message and not outcome.ok else ""
            context = append_step(context, skill, len(plan) + 1, shown)
        return PlanResult(
            prompt=prompt,
            plan=tuple(plan),
            step_scores=tuple(step_scores),
            trace=episode.finish(),
            planning_seconds=time.perf_counter() - start,
            generated=tuple(generated) if self.config.mode == "generative" else (),
            top_candidates=tuple(top),
            dialogue=turn.record(),
        )
