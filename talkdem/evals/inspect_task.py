"""TALK-Dem as an inspect_ai task (the optional extra `talkdem[inspect]`): any inspect model provider plays it.

    inspect eval talkdem/evals/inspect_task.py -T conditions=intrusion:3 -T limit=6 \\
        --model llama-cpp-python/smollm2 --model-base-url http://127.0.0.1:8000/v1

One sample per episode of the selection (`talkdem episodes` with the same `conditions` and `limit`). The
agent has one tool, `act(skill)`, which executes one of the 214 skills in the simulator and returns its
answer in words (what `talkdem/TalkDem-v0` returns); the episode ends at `done` or at the step limit. A model
that answers in text instead of calling the tool has that text executed as its action (a failed step when it
is no skill, as the simulator records it). The executed skills are kept in the sample's store
(`talkdem_plan`); the scorer is the simulator's goal check on them. `talkdem import-inspect LOG --out RUN`
turns the log into a run directory.
"""

from __future__ import annotations

from typing import Any

from inspect_ai import Task, task
from inspect_ai.dataset import MemoryDataset, Sample
from inspect_ai.model import ChatMessageSystem, ChatMessageUser
from inspect_ai.scorer import CORRECT, INCORRECT, Score, Target, accuracy, scorer, stderr
from inspect_ai.solver import Generate, Solver, TaskState, solver
from inspect_ai.tool import Tool, tool

from talkdem.evals.task_args import DEFAULT_CONDITIONS, check_task_args
from talkdem.sim.observation import observation_of
from talkdem.sim.seam import DEFAULT_MAX_STEPS, SimulatorEpisode, execute_plan, load_simulator
from talkdem.tasks import get_task

__all__ = ["PLAN_KEY", "SYSTEM_PROMPT", "goal_check", "skill_tool", "talkdem", "talkdem_agent"]

PLAN_KEY = "talkdem_plan"
SYSTEM_PROMPT = (
    "You are a household robot. Carry out the person's request by calling the `act` tool once per action. "
    "Each action is one skill: find a/an OBJECT, pick up the OBJECT, put down the OBJECT, open the OBJECT, "
    "close the OBJECT, slice the OBJECT, turn on the OBJECT, turn off the OBJECT, or done when the task is "
    "complete. The tool tells you whether the action succeeded."
)


@tool(name="act")  # type: ignore[untyped-decorator,unused-ignore]  # untyped without the inspect extra
def skill_tool(episode: SimulatorEpisode, plan: list[str]) -> Tool:
    async def execute(skill: str) -> str:
        """Execute one robot skill in the household and report what happened.

        Args:
            skill: One skill, e.g. "find an apple", "pick up the apple", "put down the apple", or "done".
        """
        if episode.over:
            return "The episode is over; no further action is taken."
        record = episode.step(skill)
        plan.append(skill)
        return observation_of(record)

    return execute


def _as_action(text: str) -> str:
    """A text answer as an action: its first non-empty line, without an `Action:` label."""
    line = next((part.strip() for part in text.splitlines() if part.strip()), "")
    return line.removeprefix("Action:").strip()


@solver  # type: ignore[untyped-decorator,unused-ignore]
def talkdem_agent(max_steps: int = DEFAULT_MAX_STEPS) -> Solver:
    async def solve(state: TaskState, generate: Generate) -> TaskState:
        episode = load_simulator().start(get_task(state.metadata["task_id"]), max_steps=max_steps)
        plan: list[str] = []
        state.tools = [skill_tool(episode, plan)]
        state.messages.insert(0, ChatMessageSystem(content=SYSTEM_PROMPT))
        turns = 0
        while not episode.over and turns < 2 * max_steps:  # bounded even if the model never acts
            turns += 1
            before = len(plan)
            state = await generate(state, tool_calls="single")
            if len(plan) == before and not episode.over:
                action = _as_action(state.output.completion)
                observation = observation_of(episode.step(action))
                plan.append(action)
                state.messages.append(ChatMessageUser(content=f"{observation} Call the act tool with the next skill."))
            state.store.set(PLAN_KEY, list(plan))
        state.store.set(PLAN_KEY, list(plan))
        return state

    return solve


@scorer(metrics=[accuracy(), stderr()])  # type: ignore[untyped-decorator,unused-ignore]
def goal_check(max_steps: int = DEFAULT_MAX_STEPS) -> Any:
    """The simulator's goal check on the executed skills (success: every ALFRED goal condition holds)."""

    async def score(state: TaskState, target: Target) -> Score:
        plan: list[str] = list(state.store.get(PLAN_KEY, []))
        trace = execute_plan(load_simulator(), get_task(state.metadata["task_id"]), plan, max_steps=max_steps)
        summary = trace.summary()
        return Score(
            value=CORRECT if trace.success else INCORRECT,
            answer=" | ".join(plan),
            metadata={
                "goal_conditions": summary["goal_conditions"],
                "hazards": summary["hazards"],
                "end_reason": trace.end_reason.value,
            },
        )

    return score


@task  # type: ignore[untyped-decorator,unused-ignore]
def talkdem(
    conditions: str | list[str] = DEFAULT_CONDITIONS, limit: int | None = None, max_steps: int = DEFAULT_MAX_STEPS
) -> Task:
    """The episodes of `talkdem episodes --conditions C --limit N`, one sample each (`-T conditions=a,b`
    reaches here as a list: inspect splits task arguments at commas). Arguments are checked here, where
    `-T` values enter (any YAML value may: `-T max_steps=abc` is a string), with one line naming the bad one."""
    args = check_task_args(
        {"conditions": conditions, "limit": limit, "max_steps": max_steps}, "talkdem inspect task (-T)"
    )
    samples = [
        Sample(
            input=instruction.text,
            target="goal reached",
            id=instruction.id,
            metadata={
                "episode_id": instruction.id,
                "task_id": instruction.task_id,
                "task_type": instruction.task_type,
                "pattern": instruction.condition.pattern,
                "level": instruction.condition.level,
            },
        )
        for instruction in args.episodes()
    ]
    return Task(
        dataset=MemoryDataset(samples, name="talkdem"),
        solver=talkdem_agent(args.max_steps),
        scorer=goal_check(args.max_steps),
        metadata={"conditions": args.conditions, "limit": args.limit, "max_steps": args.max_steps},
    )
