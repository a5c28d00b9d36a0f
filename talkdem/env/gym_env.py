"""`talkdem/TalkDem-v0`: one TALK-Dem episode per `reset`, one skill per `step` (Gymnasium's API).

Observations and actions are text. `reset` gives the instruction (and, with `show_objects`, the object types
in the scene); `step(skill)` gives the simulator's answer in words (`observation_of`). The reward is 1.0 when
the goal holds at `done`, else 0.0; `terminated` is `done`, `truncated` the step limit (30). A string outside
the 214 skills is a failed step, as the simulator records it. When an episode ends, `info` carries the goal
conditions, the hazards and the trace, so an agent's episodes can be written as a run directory
(`EpisodeRecorder`).

Which episode `reset` plays: the selection is a cycle. `reset(seed=s)` puts the cycle at an index drawn from
Gymnasium's `np_random` seeded with `s` (so the same `s` always gives the same episode, on any selection),
and each `reset()` without a seed takes the next episode of the cycle from there; an environment never
seeded starts at the selection's first episode. `options={"episode_id": ...}` plays that episode and leaves
the cycle where it is. Nothing else is random: the simulator and the simulated person are deterministic.

Every observation lies in `observation_space` whatever the action: a string outside the vocabulary is
echoed in the failure observation only as a bounded rendering (whitespace collapsed, at most 64 characters,
characters outside the space's charset shown as `?`); the trace keeps the action verbatim. An action that
is not a string is a failed step too (its `str()`). Bad constructor or `reset` arguments raise
`EnvArgumentError` (a ValueError) naming the argument and what it should be.

With `clarify="oracle"` or `"in-pattern"` the agent may also ask (the clarification track, as `talkdem run
--clarify`): a step that starts with `ask` (`info["questions"]` lists the fixed ones; free-form questions are
matched to a slot or answered "I don't know.") is answered by the simulated person, is not an action and does
not count towards the step limit. Up to `clarify_budget` questions per episode; a question past the budget goes
to the simulator like any other string, where it is a failed step. The exchanges are in `info["dialogue"]` when
the episode ends, for `EpisodeRecorder.record(..., dialogue=...)`.
"""

from __future__ import annotations

import numbers
import string
from collections.abc import Iterable, Mapping
from dataclasses import replace
from functools import cache
from typing import Any

import gymnasium as gym
from gymnasium import spaces

from talkdem.clarify import CLARIFY_MODES, ClarificationTurn, ClarifyMode, Exchange, SimulatedPerson, question_texts
from talkdem.instructions import Instruction, load_instructions
from talkdem.registry import UnknownNameError
from talkdem.schema import canonical_instruction_id
from talkdem.sim.observation import observation_of
from talkdem.sim.seam import DEFAULT_MAX_STEPS, SimulatorBackend, SimulatorEpisode, load_simulator
from talkdem.sim.trace import EpisodeTrace
from talkdem.skills import natural_name, vocabulary
from talkdem.tasks import get_task

__all__ = ["ARGUMENTS", "RESET_OPTIONS", "EnvArgumentError", "TalkDemEnv", "scene_objects"]

_MAX_TEXT = 4096
_MAX_ACTION = 64
"""The action space's longest string (the longest skill has 27 characters), and the most of an action a
failure observation repeats."""

ARGUMENTS = ("episodes", "max_steps", "simulator", "show_objects", "render_mode", "clarify", "clarify_budget")
"""The keyword arguments `TalkDemEnv` (and `gym.make(ENV_ID, ...)`) take."""

RESET_OPTIONS = ("episode_id", "show_objects")
"""The keys `reset(options=...)` understands."""


class EnvArgumentError(ValueError):
    """A `TalkDemEnv` or `reset` argument that is not what it should be (the message names both)."""


def _bad(argument: str, expected: str, got: object) -> EnvArgumentError:
    shown = repr(got)
    shown = shown if len(shown) <= 60 else shown[:57] + "..."
    return EnvArgumentError(f"TalkDem-v0: {argument} must be {expected}, got {shown} ({type(got).__name__})")


def _whole(argument: str, value: object, least: int) -> int:
    # bool is an int to Python; `max_steps=True` is a mistake, not 1. numpy integers are whole numbers.
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or value < least:
        raise _bad(argument, f"a whole number >= {least}", value)
    return int(value)


def _flag(argument: str, value: object) -> bool:
    if not isinstance(value, bool):
        raise _bad(argument, "True or False", value)
    return value


@cache
def _charset() -> str:
    """Every character an instruction, skill or observation can hold (Gymnasium's Text space needs one)."""
    chars = set(string.printable)
    for instruction in load_instructions():
        chars.update(instruction.text)
    return "".join(sorted(chars))


@cache
def _charset_set() -> frozenset[str]:
    return frozenset(_charset())


def _in_space(text: str) -> str:
    """`text` as an observation of the declared space: characters outside the charset become `?`, and the
    length is capped. Instructions, skills and simulator messages are inside already; this is the one exit
    every observation passes, so an answer or an echoed action can never leave the space."""
    charset = _charset_set()
    if len(text) > _MAX_TEXT:
        text = text[: _MAX_TEXT - 3] + "..."
    return "".join(c if c in charset else "?" for c in text)


def _shown_action(text: str) -> str:
    """How a failure observation repeats an action outside the vocabulary: on one line and at most
    `_MAX_ACTION` characters. Echoing it verbatim would let a 10 MB or multi-line action become the
    observation; the agent still learns which of its strings failed, and the trace keeps it whole."""
    flat = " ".join(text.split())
    return flat if len(flat) <= _MAX_ACTION else flat[: _MAX_ACTION - 3] + "..."


def scene_objects(task_id: str) -> tuple[str, ...]:
    """The object types present at the start of the task, as the skills name them (`apple`, `desk lamp`)."""
    from talkdem.sim.initial_state import initial_state

    state = initial_state(get_task(task_id))
    return tuple(sorted({natural_name(state.specs[o].skill_type) for o in state.present}))


class TalkDemEnv(gym.Env[str, str]):
    """The TALK-Dem benchmark as a Gymnasium environment over a selection of episodes.

    `episodes`: the episodes to play, a sequence of `Instruction`s (what `talkdem.env.select` returns) or
    episode ids (`<task_id>:clean`, `<task_id>:<pattern>:<level>`); default: all 4,800, in `talkdem
    episodes` order. `reset(seed=s)` starts the selection's cycle at an index drawn from Gymnasium's
    `np_random` seeded with `s` (the same `s`, the same episode); `reset()` takes the next episode of the
    cycle (from the first episode if the environment was never seeded). `options={"episode_id": ...}` picks
    any episode of the dataset, selected or not, without moving the cycle; `options={"show_objects": True}`
    lists the scene's objects for this episode. `max_steps`: the step limit (a whole number >= 1);
    `simulator`: a registered backend's name or a backend; `clarify`, `clarify_budget`: questions the agent
    may ask (see the module docstring). A bad argument raises `EnvArgumentError`.
    """

    metadata = {"render_modes": ["ansi"]}  # noqa: RUF012 (Gymnasium's class attribute)

    def __init__(
        self,
        episodes: Iterable[Instruction | str] | None = None,
        *,
        max_steps: int = DEFAULT_MAX_STEPS,
        simulator: str | SimulatorBackend = "symbolic",
        show_objects: bool = False,
        render_mode: str | None = None,
        clarify: ClarifyMode = "none",
        clarify_budget: int = 2,
        **unknown: object,
    ) -> None:
        # Every argument is checked here, where it enters: a wrong type must not surface later as an
        # AttributeError or TypeError from deep inside reset or step. `**unknown` catches a misspelt
        # keyword of `gym.make(...)` or `make(...)`, which Python would report as a TypeError.
        if unknown:
            raise EnvArgumentError(
                f"TalkDem-v0: unknown argument(s) {', '.join(sorted(unknown))} (known: {', '.join(ARGUMENTS)})"
            )
        if clarify not in CLARIFY_MODES:
            raise _bad("clarify", f"one of {', '.join(CLARIFY_MODES)}", clarify)
        self.clarify: ClarifyMode = clarify
        self.clarify_budget = _whole("clarify_budget", clarify_budget, 0)
        self.max_steps = _whole("max_steps", max_steps, 1)
        self.show_objects = _flag("show_objects", show_objects)
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise _bad("render_mode", "None or 'ansi'", render_mode)
        self.render_mode = render_mode
        if isinstance(simulator, str):
            try:
                self.backend = load_simulator(simulator)
            except UnknownNameError as error:  # it lists the known names
                raise EnvArgumentError(f"TalkDem-v0: simulator: {error}") from None
        elif callable(getattr(simulator, "start", None)):
            self.backend = simulator
        else:
            raise _bad("simulator", "a simulator name (symbolic, ai2thor) or a SimulatorBackend", simulator)
        # The clarification turn our planners take (`talkdem.clarify.turn`): the same rule for when a string
        # is a question (a person to ask, a question, budget left) and the same dialogue.
        self._turn = ClarificationTurn(None, self.clarify_budget)
        self._by_id = {i.id: i for i in load_instructions()}
        self.selection = self._selection(episodes)
        self.skills = tuple(skill.text for skill in vocabulary())
        charset = _charset()
        self.observation_space = spaces.Text(max_length=_MAX_TEXT, min_length=0, charset=charset)
        self.action_space = spaces.Text(max_length=_MAX_ACTION, min_length=1, charset=charset)
        self._next = 0
        """The index in `selection` of the episode the next unseeded `reset()` plays."""
        self._episode: SimulatorEpisode | None = None
        self.instruction: Instruction | None = None
        self.trace: EpisodeTrace | None = None
        """The finished episode's trace (None while it runs)."""
        self._last = ""

    def _selection(self, episodes: Iterable[Instruction | str] | None) -> tuple[Instruction, ...]:
        if episodes is None:
            return load_instructions()
        expected = "a sequence of Instructions (talkdem.env.select(...)) or episode ids"
        # A string is iterable too: `episodes="clean"` would otherwise be five one-letter "episodes".
        if isinstance(episodes, str | bytes | Mapping) or not isinstance(episodes, Iterable):
            raise _bad("episodes", expected, episodes)
        chosen = []
        for index, item in enumerate(episodes):
            if isinstance(item, str):
                chosen.append(self._by_episode_id(item, f"episodes[{index}]"))
            elif isinstance(item, Instruction):
                try:
                    get_task(item.task_id)  # a hand-made Instruction must name a task the simulator has
                except KeyError as error:
                    raise EnvArgumentError(f"TalkDem-v0: episodes[{index}] ('{item.id}'): {error.args[0]}") from None
                chosen.append(item)
            else:
                raise _bad(f"episodes[{index}]", "an Instruction or an episode id", item)
        if not chosen:
            raise EnvArgumentError("TalkDem-v0: episodes must hold at least one episode, got an empty selection")
        return tuple(chosen)

    def _by_episode_id(self, episode_id: object, argument: str) -> Instruction:
        if not isinstance(episode_id, str):
            raise _bad(argument, "an episode id string", episode_id)
        try:
            canonical = canonical_instruction_id(episode_id)
        except ValueError as error:  # names the expected shape
            raise EnvArgumentError(f"TalkDem-v0: {argument}: {error}") from None
        if canonical not in self._by_id:
            raise EnvArgumentError(f"TalkDem-v0: {argument}: unknown episode id '{episode_id}'")
        return self._by_id[canonical]

    def _options(self, options: object) -> tuple[Instruction | None, bool]:
        """(the episode `options` asks for, if any; whether to show the scene's objects)."""
        if options is None:
            return None, self.show_objects
        if not isinstance(options, dict):
            raise _bad("reset options", f"None or a dict with keys {', '.join(RESET_OPTIONS)}", options)
        unknown = sorted(str(key) for key in options if key not in RESET_OPTIONS)
        if unknown:
            raise EnvArgumentError(
                f"TalkDem-v0: reset options: unknown key(s) {', '.join(unknown)} (known: {', '.join(RESET_OPTIONS)})"
            )
        episode_id = options.get("episode_id")
        chosen = None if episode_id is None else self._by_episode_id(episode_id, "options['episode_id']")
        show = options.get("show_objects")
        return chosen, self.show_objects or (show is not None and _flag("options['show_objects']", show))

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None) -> tuple[str, dict[str, Any]]:
        # Gymnasium's own seed check raises gymnasium.error.Error, which is no ValueError.
        seed = None if seed is None else _whole("seed", seed, 0)
        chosen, show = self._options(options)
        super().reset(seed=seed)
        if seed is not None:
            # The seed places the cycle (and nothing else is random): one draw from the generator Gymnasium
            # has just seeded, so the same seed plays the same episode and unseeded resets go on from there.
            self._next = int(self.np_random.integers(len(self.selection)))
        instruction = chosen
        if instruction is None:
            instruction = self.selection[self._next]
            self._next = (self._next + 1) % len(self.selection)
        task = get_task(instruction.task_id)
        self.instruction, self.trace = instruction, None
        self._episode = self.backend.start(task, max_steps=self.max_steps)
        person = SimulatedPerson(self.clarify, instruction, task) if self.clarify != "none" else None
        self._turn = ClarificationTurn(person, self.clarify_budget)
        objects = scene_objects(instruction.task_id) if show else ()
        observation = _in_space(
            instruction.text + (f"\nObjects in the scene: {', '.join(objects)}." if objects else "")
        )
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
        if person is not None:
            info.update(questions=question_texts(), clarify=self.clarify, clarify_budget=self.clarify_budget)
        return observation, info

    def step(self, action: str) -> tuple[str, float, bool, bool, dict[str, Any]]:
        if self._episode is None or self.instruction is None:
            raise RuntimeError("TalkDem-v0: call reset() before step()")
        if self.trace is not None:
            raise RuntimeError(f"TalkDem-v0: episode '{self.instruction.id}' is over; call reset()")
        # Not a string (None from an agent's failed parse, a number): its text is the step, a failed one.
        text = action if isinstance(action, str) else str(action)
        exchange = self._turn.ask(text, len(self._episode.steps))
        if exchange is not None:
            return self._answered(exchange)
        record = self._episode.step(text)
        # The sentence every planner reads, with the action as a failure may repeat it (`_shown_action`).
        observation = _in_space(observation_of(replace(record, skill=_shown_action(record.skill))))
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
            dialogue = self._turn.record()
            if dialogue is not None:
                info["dialogue"] = dialogue
        return observation, reward, terminated, truncated, info

    @property
    def dialogue(self) -> list[Exchange]:
        """The questions asked and answered in the current episode."""
        return self._turn.dialogue

    def _answered(self, exchange: Exchange) -> tuple[str, float, bool, bool, dict[str, Any]]:
        """A question: the simulated person's answer is the observation; the simulator does not move."""
        assert self.instruction is not None
        answer = _in_space(exchange.answer)
        self._last = answer
        info: dict[str, Any] = {
            "episode_id": self.instruction.id,
            "question": exchange.question,
            "slot": exchange.slot,
            "answer": exchange.answer,
            "in_pattern": exchange.in_pattern,
            "questions_left": self.clarify_budget - len(self.dialogue),
        }
        return answer, 0.0, False, False, info

    def finish(self) -> EpisodeTrace:
        """End the current episode where it stands (an agent that stops without `done`): its trace."""
        if self._episode is None:
            raise RuntimeError("TalkDem-v0: call reset() first")
        if self.trace is None:
            self.trace = self._episode.finish()
        return self.trace

    def render(self) -> str | None:
        return self._last if self.render_mode == "ansi" else None
