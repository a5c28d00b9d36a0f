"""Bring your own agent: TALK-Dem as a Gymnasium environment, episode selections, and a run recorder.

    import gymnasium as gym
    import talkdem.env                      # registers talkdem/TalkDem-v0
    env = gym.make("talkdem/TalkDem-v0", episodes=talkdem.env.select("clean", limit=6))

Gymnasium is imported only when the environment is built (`make`, `register_env`, or `TalkDemEnv`), so
importing this package, `talkdem --help` and the simulator stay fast.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from talkdem.env.recorder import AGENT_RESUME_KEYS, EpisodeRecorder
from talkdem.sim.observation import observation_of

if TYPE_CHECKING:
    from talkdem.env.gym_env import EnvArgumentError, TalkDemEnv
    from talkdem.instructions import Instruction

__all__ = [
    "AGENT_RESUME_KEYS",
    "ENV_ID",
    "EnvArgumentError",
    "EpisodeRecorder",
    "TalkDemEnv",
    "make",
    "observation_of",
    "register_env",
    "select",
]

ENV_ID = "talkdem/TalkDem-v0"


def register_env() -> None:
    """Register `talkdem/TalkDem-v0` with Gymnasium (idempotent)."""
    import gymnasium

    if ENV_ID not in gymnasium.registry:
        gymnasium.register(id=ENV_ID, entry_point="talkdem.env.gym_env:TalkDemEnv", disable_env_checker=True)


def select(conditions: str | None = None, limit: int | None = None) -> list[Instruction]:
    """Exactly the episodes `talkdem run --conditions C --limit N` plans (and `talkdem episodes` lists)."""
    from talkdem.runs.sampling import select_episodes
    from talkdem.schema import parse_conditions

    return select_episodes(parse_conditions(conditions), limit)


def make(**kwargs: Any) -> TalkDemEnv:
    """`gymnasium.make(ENV_ID, **kwargs).unwrapped` without the registry: the environment itself."""
    from talkdem.env.gym_env import TalkDemEnv

    return TalkDemEnv(**kwargs)


def __getattr__(name: str) -> Any:
    if name in ("TalkDemEnv", "EnvArgumentError"):  # they import gymnasium: only when asked for
        from talkdem.env import gym_env

        return getattr(gym_env, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def _register_if_available() -> None:
    # `import talkdem.env` is how a Gymnasium user asks for the id; without gymnasium there is nothing to do.
    import importlib.util

    if importlib.util.find_spec("gymnasium") is not None:
        register_env()


_register_if_available()
