"""`talkdem/TalkDem-v0`: one TALK-Dem episode per `reset`, one skill per `step` (Gymnasium's API).

Observations and actions are text. `reset` gives the instruction (and, with `show_objects`, the object types
in the scene); `step(skill)` gives the simulator's answer in words (`observation_of`). The reward is 1.0 when
the goal holds at `done`, else 0.0; `terminated` is `done`, `truncated` the step limit (30). A string outside
the 214 skills is a failed step, as the simulator records it. When an episode ends, `info` carries the goal
conditions, the hazards and the trace, so an agent's episodes can be written as a run directory
(`EpisodeRecorder`). Nothing is random: `seed` is accepted for the API and changes nothing.

With `clarify="oracle"` or `"in-pattern"` the agent may also ask (the clarification track, as `talkdem run
--clarify`): a step that starts with `ask` (`info["questions"]` lists the fixed ones; free-form questions are
matched to a slot or answered "I don't know.") is answered by the simulated person, is not an action and does
not count towards the step limit. Up to `clarify_budget` questions per episode; a question past the budget goes
to the simulator like any other string, where it is a failed step. The exchanges are in `info["dialogue"]` when
the episode ends, for `EpisodeRecorder.record(..., dialogue=...)`.
"""

from __future__ import annotations

import string
from collections.abc import Sequence
from functools import cache
from typing import Any

import gymnasium as gym
from gymnasium import spaces

from talkdem.clarify import CLARIFY_MODES, ClarifyMode, Exchange, SimulatedPerson, is_question, question_texts
from talkdem.instructions import Instruction, load_instructions
from talkdem.schema import parse_instruction_id
from talkdem.sim.observation import observation_of
from talkdem.sim.seam import DEFAULT_MAX_STEPS, SimulatorBackend, SimulatorEpisode, load_simulator
from talkdem.sim.trace import EpisodeTrace
from talkdem.skills import natural_name, vocabulary
from talkdem.tasks import get_task

__all__ = ["TalkDemEnv", "scene_objects"]

_MAX_TEXT = 4096


@cache
def _charset() -> str:
    """Every character an instruction, skill or observation can hold (Gymnasium's Text space needs one)."""
    chars = set(string.printable)
    for instruction in load_instructions():
        chars.update(instruction.text)
    return "".join(sorted(chars))


def scene_objects(task_id: str) -> tuple[str, ...]:
    """The object types present at the start of the task, as the skills name them (`apple`, `desk lamp`)."""
    from talkdem.sim.initial_state import initial_state

    state = initial_state(get_task(task_id))
    return tuple(sorted({natural_name(state.specs[o].skill_type) for o in state.present}))


class TalkDemEnv(gym.Env[str, str]):
    """The TALK-Dem benchmark as a Gymnasium environment over a selection of episodes.

    `episodes`: the instructions to iterate (default: all 4,800, in `talkdem episodes` order); `reset()`
    without an `episode_id` option takes the next one, cycling. `options={"episode_id": ...}` picks any
    episode of the dataset, selected or not. `clarify`, `clarify_budget`: questions the agent may ask (see the
    module docstring).
    """

    metadata = {"render_modes": ["ansi"]}  # noqa: RUF012 (Gymnasium's class attribute)

    def __init__(
        self,
        episodes: Sequence[Instruction] | None = None,
        *,
        max_steps: int = DEFAULT_MAX_STEPS,
        simulator: str | SimulatorBackend = "symbolic",
        show_objects: bool = False,
        render_mode: str | None = None,
        clarify: ClarifyMode = "none",
        clarify_budget: int = 2,
    ) -> None:
        if clarify not in CLARIFY_MODES:
            raise ValueError(f"TalkDem-v0: clarify must be one of {', '.join(CLARIFY_MODES)}, got {clarify!r}")
        if isinstance(clarify_budget, bool) or not isinstance(clarify_budget, int) or clarify_budget < 0:
            raise ValueError(f"TalkDem-v0: clarify_budget must be a whole number >= 0, got {clarify_budget!r}")
        self.clarify: ClarifyMode = clarify
        self.clarify_budget = clarify_budget
        self._person: SimulatedPerson | None = None
        self.dialogue: list[Exchange] = []
        """The questions asked and answered in the current episode."""
        self.selection = tuple(episodes) if episodes is not None else load_instructions()
        if not self.selection:
            raise ValueError("TalkDem-v0: the episode selection is empty")
        self.max_steps = max_steps
        self.backend = load_simulator(simulator) if isinstance(simulator, str) else simulator
        self.show_objects = show_objects
        self.render_mode = render_mode
        self.skills = tuple(skill.text for skill in vocabulary())
        charset = _charset()
        self.observation_space = spaces.Text(max_length=_MAX_TEXT, min_length=0, charset=charset)
        self.action_space = spaces.Text(max_length=64, min_length=1, charset=charset)
        self._by_id = {i.id: i for i in load_instructions()}
        self._next = 0
        self._episode: SimulatorEpisode | None = None
        self.instruction: Instruction | None = None
        self.trace: EpisodeTrace | None = None
        """The finished episode's trace (None while it runs)."""
        self._last = ""

    def _pick(self, options: dict[str, Any] | None) -> Instruction:
        episode_id = (options or {}).get("episode_id")
        if episode_id is None:
            chosen = self.selection[self._next % len(self.selection)]
            self._next += 1
            return chosen
        if not isinstance(episode_id, str):
            raise ValueError(f"TalkDem-v0: options['episode_id'] must be a string, got {type(episode_id).__name__}")
        task_id, condition = parse_instruction_id(episode_id)  # names the expected shape when malformed
        canonical = f"{task_id}:{condition.pattern}:{condition.level}"
        if canonical not in self._by_id:
            raise ValueError(f"TalkDem-v0: unknown episode id '{episode_id}'")
        return self._by_id[canonical]

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None) -> tuple[str, dict[str, Any]]:
        super().reset(seed=seed)
        instruction = self._pick(options)
        task = get_task(instruction.task_id)
        self.instruction, self.trace = instruction, None
        self._episode = self.backend.start(task, max_steps=self.max_steps)
        self._person = SimulatedPerson(self.clarify, instruction, task) if self.clarify != "none" else None
        self.dialogue = []
        show = self.show_objects or bool((options or {}).get("show_objects"))
        objects = scene_objects(instruction.task_id) if show else ()
        observation = instruction.text + (f"\nObjects in the scene: {', '.join(objects)}." if objects else "")
        self._last = observation
        info: dict[str, Any] = {
            "episode_id": instruction.id,
            "task_id": instruction.task_id,
            "task_type": instruction.task_type,
            "pattern": instruction.condition.pattern,
            "level": instruction.condition.level,
            "admissible_skills": self.skills,
            "max_steps": self.max_steps,
        }
        if objects:
            info["objects"] = objects
        if self._person is not None:
            info.update(questions=question_texts(), clarify=self.clarify, clarify_budget=self.clarify_budget)
        return observation, info

    def step(self, action: str) -> tuple[str, float, bool, bool, dict[str, Any]]:
        if self._episode is None or self.instruction is None:
            raise RuntimeError("TalkDem-v0: call reset() before step()")
        if self.trace is not None:
            raise RuntimeError(f"TalkDem-v0: episode '{self.instruction.id}' is over; call reset()")
        text = action if isinstance(action, str) else str(action)
        if self._person is not None and is_question(text) and len(self.dialogue) < self.clarify_budget:
            return self._ask(text)
        record = self._episode.step(text)
        observation = observation_of(record)
        self._last = observation
        info: dict[str, Any] = {
            "episode_id": self.instruction.id,
            "step": record.index,
            "skill": record.parsed,
            "ok": record.ok,
            "message": record.message,
            "in_vocabulary": record.parsed is not None,
        }
        terminated, truncated = self._episode.done, self._episode.truncated
        reward = 0.0
        if terminated or truncated:
            self.trace = self._episode.finish()
            reward = 1.0 if terminated and self.trace.success else 0.0
            summary = self.trace.summary()
            info.update(
                success=self.trace.success,
                goal_conditions=summary["goal_conditions"],
                conditions={c.name: c.met for c in self.trace.goal.conditions},
                hazards=summary["hazards"],
                end_reason=self.trace.end_reason.value,
                trace=self.trace,
            )
            if self._person is not None:
                info["dialogue"] = tuple(self.dialogue)
        return observation, reward, terminated, truncated, info

    def _ask(self, question: str) -> tuple[str, float, bool, bool, dict[str, Any]]:
        """A question: the simulated person's answer is the observation; the simulator does not move."""
        assert self._person is not None and self.instruction is not None
        assert self._episode is not None
        exchange = self._person.ask(question, len(self._episode.steps))
        self.dialogue.append(exchange)
        self._last = exchange.answer
        info: dict[str, Any] = {
            "episode_id": self.instruction.id,
            "question": exchange.question,
            "slot": exchange.slot,
            "answer": exchange.answer,
            "in_pattern": exchange.in_pattern,
            "questions_left": self.clarify_budget - len(self.dialogue),
        }
        return exchange.answer, 0.0, False, False, info

    def finish(self) -> EpisodeTrace:
        """End the current episode where it stands (an agent that stops without `done`): its trace."""
        if self._episode is None:
            raise RuntimeError("TalkDem-v0: call reset() first")
        if self.trace is None:
            self.trace = self._episode.finish()
        return self.trace

    def render(self) -> str | None:
        return self._last if self.render_mode == "ansi" else None
