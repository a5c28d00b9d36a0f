"""docs/agents.md's "Bring your own agent" example, run as written, then replayed over all 300 benchmark tasks; and
the README's short loop ("Drive the Gymnasium environment"), run as written, printing what it says."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import pytest

from talkdem.sim import run_plan
from talkdem.tasks import get_task

ROOT = Path(__file__).resolve().parents[2]
AGENTS = ROOT / "docs" / "agents.md"
README = ROOT / "README.md"


def _python_block(page: Path, heading: str) -> str:
    section = page.read_text(encoding="utf-8").split(f"\n{heading}\n", 1)[1]
    match = re.search(r"```python\n(.*?)```", section, re.S)
    assert match, f"{page.name}: the section {heading!r} has no python example"
    return match.group(1)


def _example() -> str:
    return _python_block(AGENTS, "## Bring your own agent")


@pytest.fixture(scope="module")
def example(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    import os

    here = os.getcwd()
    os.chdir(tmp_path_factory.mktemp("agent"))
    try:
        namespace: dict[str, Any] = {"__name__": "readme_example"}
        exec(compile(_example(), str(AGENTS), "exec"), namespace)
        namespace["cwd"] = Path.cwd()
    finally:
        os.chdir(here)
    return namespace


def test_the_example_records_a_run_that_report_accepts(example: dict[str, Any]) -> None:
    from talkdem.report.runs import score_runs
    from talkdem.runs import read_episodes, read_header

    run_dir = example["cwd"] / "runs" / "replay-agent"
    header = read_header(run_dir)
    assert header.model == {"backend": "agent", "name": "replay-agent", "revision": "1.0"}
    assert header.config["agent"]["version"] == "1.0" and header.config["planned_episodes"] == 12
    assert header.status == "complete", "every planned episode was recorded"
    records = read_episodes(run_dir)
    assert [r.episode_id for r in records] == [i.id for i in example["episodes"]]
    assert all(r.success for r in records)
    (run,) = score_runs([run_dir], bootstrap=0)
    assert run.label == "replay-agent / external"
    assert run.coverage.complete


def _agent_with(example: dict[str, Any], plan_of: Any) -> Any:
    class Agent(example["ReplayAgent"]):  # type: ignore[misc]
        def reset(self, observation: str, info: dict[str, Any]) -> None:
            super().reset(observation, info)
            self.todo = plan_of(self.todo)

    return Agent()


def test_every_reference_plan_earns_reward_one_and_a_wrong_order_zero(example: dict[str, Any]) -> None:
    import gymnasium as gym

    import talkdem.env

    clean = talkdem.env.select("clean")
    assert len(clean) == 300
    env = gym.make("talkdem/TalkDem-v0", episodes=clean)
    replay = example["ReplayAgent"]()

    def done_first(plan: list[str]) -> list[str]:
        # `done` before the work: the episode ends there (no step after `done` is executed), goal unmet
        return ["done", *plan]

    def reversed_steps(plan: list[str]) -> list[str]:
        return [*reversed([s for s in plan if s != "done"]), "done"]

    early, backwards = _agent_with(example, done_first), _agent_with(example, reversed_steps)
    for instruction in clean:
        plan, reward, info = example["play"](env, replay, instruction.id)
        assert reward == 1.0 and info["success"] and plan[-1] == "done", instruction.id
        assert info["goal_conditions"]["met"] == info["goal_conditions"]["total"]
        plan, reward, info = example["play"](env, early, instruction.id)
        assert (reward, plan, info["success"]) == (0.0, ["done"], False), instruction.id
        # Reversed steps rarely reach the goal (a lamp already in reach can make them); live = stored, always.
        plan, reward, info = example["play"](env, backwards, instruction.id)
        stored = run_plan(get_task(instruction.task_id), plan)
        assert reward == float(stored.success) and info["trace"].state_hash == stored.state_hash, instruction.id


def test_the_environment_reports_failures_limits_and_bad_ids() -> None:
    import gymnasium as gym

    import talkdem.env

    env = gym.make("talkdem/TalkDem-v0", show_objects=True)
    first = talkdem.env.select("clean", limit=1)[0]
    observation, info = env.reset(seed=3, options={"episode_id": first.id})
    assert observation.startswith(first.text) and "Objects in the scene:" in observation
    assert len(info["admissible_skills"]) == 214 and info["task_type"] == first.task_type
    observation, reward, terminated, truncated, info = env.step("teleport home")
    assert observation == "teleport home: failed (instruction not supported)."
    assert (reward, terminated, truncated, info["in_vocabulary"]) == (0.0, False, False, False)
    for _ in range(29):
        observation, reward, terminated, truncated, info = env.step("find an apple")
    assert truncated and not terminated and reward == 0.0 and info["end_reason"] == "step_limit"
    with pytest.raises(RuntimeError, match="is over"):
        env.step("done")
    with pytest.raises(ValueError, match="unknown episode id"):
        env.reset(options={"episode_id": "trial_nope:clean:0"})
    with pytest.raises(ValueError, match="<task_id>"):
        env.reset(options={"episode_id": "not an id"})


def test_the_readme_loop_plays_an_episode_to_reward_one(capsys: pytest.CaptureFixture[str]) -> None:
    block = _python_block(README, "### Drive the Gymnasium environment")
    exec(compile(block, str(README), "exec"), {"__name__": "readme_loop"})
    stated = re.search(r"^print\(.*\)  # (.+?):", block, flags=re.MULTILINE)
    assert stated is not None, "the README's loop states what it prints"
    assert capsys.readouterr().out.splitlines() == [stated.group(1)]  # "1.0 True"
