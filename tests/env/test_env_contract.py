"""TalkDem-v0 keeps Gymnasium's contract: Gymnasium's own checker passes on any selection, a seed chooses the
same episode every time, every observation lies in `observation_space` whatever the action, and a bad
constructor or `reset` argument is one `EnvArgumentError` (a ValueError) naming the argument."""

from __future__ import annotations

from functools import cache
from typing import Any

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env
from hypothesis import given, settings
from hypothesis import strategies as st

import talkdem.env
from talkdem.env import ENV_ID, EnvArgumentError, TalkDemEnv, make, select
from talkdem.env.gym_env import ARGUMENTS, RESET_OPTIONS
from talkdem.instructions import Instruction


@pytest.fixture(scope="module")
def sixteen() -> list[Instruction]:
    episodes = select("clean,intrusion:3", limit=8)  # the limit counts tasks: 8 tasks, 2 conditions each
    assert len(episodes) == 16
    return episodes


def _ids(env: TalkDemEnv, resets: list[dict[str, Any]]) -> list[str]:
    return [env.reset(**kwargs)[1]["episode_id"] for kwargs in resets]


@pytest.mark.filterwarnings("ignore:.*render fps:UserWarning")
@pytest.mark.parametrize("size", [1, 2, 16])
@pytest.mark.parametrize("clarify", ["none", "in-pattern"])
def test_gymnasiums_checker_passes(size: int, clarify: str, sixteen: list[Instruction]) -> None:
    # Through gym.make, so the env has a spec and the checker renders every declared mode too.
    env = gym.make(ENV_ID, episodes=sixteen[:size], clarify=clarify)
    check_env(env.unwrapped)
    env = gym.make(ENV_ID, episodes=sixteen[:size], render_mode="ansi")
    check_env(env.unwrapped)


@pytest.mark.parametrize("size", [1, 2, 16])
def test_a_seed_plays_the_same_episode_every_time(size: int, sixteen: list[Instruction]) -> None:
    env = make(episodes=sixteen[:size])
    for seed in range(12):
        first = _ids(env, [{"seed": seed}, {}, {}])
        env.reset()  # wherever the cycle stands, the seed puts it back
        assert _ids(env, [{"seed": seed}, {}, {}]) == first, seed
        assert _ids(make(episodes=sixteen[:size]), [{"seed": seed}, {}, {}]) == first, "another env, the same"
        assert set(first) <= {i.id for i in sixteen[:size]}


def test_seeds_spread_over_the_selection_and_unseeded_resets_go_round_it(sixteen: list[Instruction]) -> None:
    env = make(episodes=sixteen)
    picked = {env.reset(seed=seed)[1]["episode_id"] for seed in range(64)}
    assert len(picked) >= 8, "the seed chooses among the episodes, not always the same one"
    start = env.reset(seed=5)[1]["episode_id"]
    order = [i.id for i in sixteen]
    cycle = [start, *_ids(env, [{}] * 16)]
    offset = order.index(start)
    assert cycle == [order[(offset + k) % 16] for k in range(17)], "the next resets continue the cycle"


def test_an_unseeded_environment_plays_the_selection_in_order(sixteen: list[Instruction]) -> None:
    env = make(episodes=sixteen[:3])
    assert _ids(env, [{}] * 4) == [i.id for i in (*sixteen[:3], sixteen[0])]


def test_an_episode_id_is_played_and_leaves_the_cycle_where_the_seed_put_it(sixteen: list[Instruction]) -> None:
    env = make(episodes=sixteen)
    seeded = _ids(env, [{"seed": 9}, {}])
    outside = select("intrusion:1", limit=1)[0].id  # not in the selection: any episode of the dataset
    played = _ids(env, [{"seed": 9, "options": {"episode_id": outside}}, {}, {}])
    assert played == [outside, *seeded]
    env.reset(seed=np.int64(9))  # type: ignore[arg-type]  # numpy integers are whole numbers too
    assert env.instruction is not None and env.instruction.id == seeded[0]


_HOSTILE_ACTIONS: list[object] = [
    "é" * 3,
    "x" * 10_000_000,
    "",
    "   \n\t ",
    "\x00\x1b[31m",
    "pick up the 🍎",
    "find an apple\n" * 500,
    5,
    None,
    b"find an apple",
    ["find an apple"],
    "ask which object to use " + "ü" * 5000,
]


@pytest.mark.parametrize("clarify", ["none", "oracle", "in-pattern"])
def test_every_observation_is_in_the_space_whatever_the_action(clarify: str, sixteen: list[Instruction]) -> None:
    env = make(episodes=sixteen, clarify=clarify, clarify_budget=3, max_steps=len(_HOSTILE_ACTIONS) + 1)
    observation, _ = env.reset(seed=0)
    assert observation in env.observation_space
    for action in _HOSTILE_ACTIONS:
        observation, *_ = env.step(action)  # type: ignore[arg-type]
        assert observation in env.observation_space, repr(action)[:40]
        assert len(observation) <= 200, "a failure repeats at most 64 characters of the action"
    assert env.trace is None
    trace = env.finish()
    assert "x" * 10_000_000 in [s.skill for s in trace.steps], "the trace keeps the action verbatim"


def test_a_failure_repeats_a_readable_action_and_bounds_the_rest() -> None:
    env = make(episodes=select("clean", limit=1))
    env.reset()
    assert env.step("teleport home")[0] == "teleport home: failed (instruction not supported)."
    assert env.step("teleport\n  home")[0] == "teleport home: failed (instruction not supported)."
    assert env.step("téléport")[0] == "t?l?port: failed (instruction not supported)."
    long = env.step("y" * 1000)[0]
    assert long == "y" * 61 + "...: failed (instruction not supported)."
    assert env.step(None)[0] == "None: failed (instruction not supported)."  # type: ignore[arg-type]
    assert env.step("")[0] == "(empty action): failed (instruction not supported)."


@settings(max_examples=60, deadline=None)
@given(action=st.text(max_size=300))
def test_any_text_action_gives_an_observation_in_the_space(action: str) -> None:
    env = _shared_env()
    if env.trace is not None or env.instruction is None:
        env.reset()
    observation, *_ = env.step(action)
    assert observation in env.observation_space


@cache
def _shared_env() -> TalkDemEnv:
    """One environment for every example (building one per example would be most of the test's time)."""
    return make(episodes=select("clean", limit=2), clarify="oracle", clarify_budget=1000)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"episodes": "clean"}, "episodes must be a sequence of Instructions .* or episode ids, got 'clean' \\(str\\)"),
        ({"episodes": b"clean"}, "episodes must be a sequence"),
        ({"episodes": 5}, "episodes must be a sequence"),
        ({"episodes": {"a": 1}}, "episodes must be a sequence"),
        ({"episodes": []}, "episodes must hold at least one episode"),
        ({"episodes": [1]}, "episodes\\[0\\] must be an Instruction or an episode id, got 1 \\(int\\)"),
        ({"episodes": ["clean"]}, "episodes\\[0\\]: 'clean' is not an instruction id \\(<task_id>:clean"),
        ({"episodes": ["trial_nope:clean:0"]}, "episodes\\[0\\]: unknown episode id 'trial_nope:clean:0'"),
        ({"max_steps": "30"}, "max_steps must be a whole number >= 1, got '30' \\(str\\)"),
        ({"max_steps": 0}, "max_steps must be a whole number >= 1, got 0"),
        ({"max_steps": 2.5}, "max_steps must be a whole number >= 1"),
        ({"max_steps": True}, "max_steps must be a whole number >= 1, got True \\(bool\\)"),
        ({"clarify_budget": "2"}, "clarify_budget must be a whole number >= 0"),
        ({"clarify": "maybe"}, "clarify must be one of none, oracle, in-pattern"),
        ({"show_objects": "yes"}, "show_objects must be True or False, got 'yes'"),
        pytest.param(
            {"render_mode": "human"},
            "render_mode must be None or 'ansi', got 'human'",
            marks=pytest.mark.filterwarnings("ignore:.*render_mode='human':UserWarning"),  # gym.make's own word
        ),
        ({"simulator": "nope"}, "simulator: unknown simulator backend 'nope' \\(known: symbolic"),
        ({"simulator": 5}, "simulator must be a simulator name .* or a SimulatorBackend, got 5"),
        ({"max_step": 3}, "unknown argument\\(s\\) max_step \\(known: episodes, max_steps"),
    ],
)
def test_a_bad_constructor_argument_is_one_named_value_error(kwargs: dict[str, Any], message: str) -> None:
    for build in (make, lambda **kw: gym.make(ENV_ID, **kw)):
        with pytest.raises(EnvArgumentError, match=f"^TalkDem-v0: {message}") as caught:
            build(**kwargs)
        assert isinstance(caught.value, ValueError) and "\n" not in str(caught.value)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"options": "x"}, "reset options must be None or a dict with keys episode_id, show_objects, got 'x'"),
        ({"options": ["episode_id"]}, "reset options must be None or a dict"),
        ({"options": {"episode": "x"}}, "reset options: unknown key\\(s\\) episode \\(known: episode_id"),
        ({"options": {"episode_id": 3}}, "options\\['episode_id'\\] must be an episode id string, got 3"),
        ({"options": {"episode_id": "not an id"}}, "options\\['episode_id'\\]: 'not an id' is not an instruction id"),
        ({"options": {"show_objects": 1}}, "options\\['show_objects'\\] must be True or False, got 1"),
        ({"seed": -1}, "seed must be a whole number >= 0, got -1"),
        ({"seed": 1.5}, "seed must be a whole number >= 0, got 1.5 \\(float\\)"),
        ({"seed": "7"}, "seed must be a whole number >= 0, got '7' \\(str\\)"),
    ],
)
def test_a_bad_reset_argument_is_one_named_value_error(kwargs: dict[str, Any], message: str) -> None:
    env = make(episodes=select("clean", limit=2))
    with pytest.raises(EnvArgumentError, match=f"^TalkDem-v0: {message}") as caught:
        env.reset(**kwargs)
    assert "\n" not in str(caught.value)
    assert env.reset(options={})[1]["episode_id"], "a refused reset leaves the environment usable"


def test_the_documented_names_are_the_real_ones() -> None:
    import inspect

    parameters = inspect.signature(TalkDemEnv.__init__).parameters
    assert tuple(name for name in parameters if name not in ("self", "unknown")) == ARGUMENTS
    env = make(episodes=select("clean", limit=1))
    _, info = env.reset(options={"episode_id": select("clean", limit=1)[0].id, "show_objects": True})
    assert set(RESET_OPTIONS) == {"episode_id", "show_objects"} and info["objects"]
    assert talkdem.env.EnvArgumentError is EnvArgumentError and "EnvArgumentError" in talkdem.env.__all__
