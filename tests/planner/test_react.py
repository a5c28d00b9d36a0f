"""The ReAct loop around the model: thought, action, observation; actions always executed as the simulator would."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from talkdem.llm.interface.base import LanguageModel, ModelIdentity
from talkdem.llm.interface.requests import GenerateRequest, LoglikelihoodRequest
from talkdem.planner import PlannerInput
from talkdem.planner.react import REACT_HEADER, ReActConfig, ReActPlanner
from talkdem.sim import FailureKind
from talkdem.tasks import TaskSet, load_tasks

TASK = next(t for t in load_tasks(TaskSet.BENCHMARK) if t.task_type == "pick_and_place_simple")


class ScriptedReAct(LanguageModel):
    """Prefers, after the query's n-th `Action:`, the n-th skill of a script; thoughts are fixed text."""

    def __init__(self, script: Sequence[str], *, chat: bool = False, thought: str = "I will act now. And more") -> None:
        self.script = list(script)
        self.thought = thought
        self.supports_loglikelihood = not chat
        self.identity = ModelIdentity("scripted", "scripted-react", "1")
        self.contexts: list[str] = []

    def _wanted(self, context: str) -> str:
        taken = context.rsplit("Task: ", 1)[-1].count("Action:") - 1
        return self.script[min(max(taken, 0), len(self.script) - 1)]

    def loglikelihood(self, requests: Sequence[LoglikelihoodRequest]) -> list[float]:
        self.contexts += [r.context for r in requests[:1]]
        return [0.0 if r.continuation.strip() == self._wanted(r.context) else -5.0 for r in requests]

    def generate(self, requests: Sequence[GenerateRequest]) -> list[str]:
        out = []
        for r in requests:
            if r.prompt.endswith("Thought:"):
                assert "." in r.stop and r.max_new_tokens == 24  # a sentence end and a budget keep it short
                out.append(self.thought.split(".")[0])
            else:
                out.append(self._wanted(r.prompt))
        return out


def test_reference_plan_is_followed_with_a_thought_per_step() -> None:
    model = ScriptedReAct(TASK.reference_plan)
    result = ReActPlanner(model).plan(TASK, PlannerInput("Put it there."))
    assert result.plan == TASK.reference_plan and result.trace.success
    assert result.generated == ("I will act now.",) * len(TASK.reference_plan)
    assert result.prompt.startswith(REACT_HEADER) and result.prompt.endswith("Task: Put it there.\n")


def test_the_model_reads_the_simulators_failure_message() -> None:
    model = ScriptedReAct(["pick up the apple", "done"])
    result = ReActPlanner(model).plan(TASK, PlannerInput("x"))
    assert result.plan == ("pick up the apple", "done")
    assert not result.trace.steps[0].ok
    message = result.trace.steps[0].message.rstrip(".")
    assert f"Action: pick up the apple\nObservation: pick up the apple: failed ({message}).\n" in model.contexts[-1]


def test_the_step_limit_ends_a_looping_agent() -> None:
    result = ReActPlanner(ScriptedReAct(["find an apple"]), ReActConfig(max_steps=5)).plan(TASK, PlannerInput("x"))
    assert len(result.plan) == 5 and result.trace.end_reason.value == "step_limit"


def test_chat_actions_are_parsed_and_nonsense_is_a_failed_step() -> None:
    model = ScriptedReAct(["Find An Apple.", "fly to the moon", "done"], chat=True)
    result = ReActPlanner(model).plan(TASK, PlannerInput("x"))
    assert result.plan == ("find an apple", "fly to the moon", "done")
    assert result.trace.steps[1].failure is FailureKind.NOT_SUPPORTED


def test_a_react_run_directory_keeps_the_thoughts(tmp_path: Path) -> None:
    from talkdem.planner.strategies import load_strategy
    from talkdem.runs import read_episodes, read_header
    from talkdem.runs.runner import run_episodes
    from talkdem.runs.sampling import select_episodes
    from talkdem.schema import parse_conditions

    episodes = select_episodes(parse_conditions("clean"), 2)
    model = ScriptedReAct(["find an apple", "done"])
    summary = run_episodes(episodes, model, load_strategy("vanilla"), tmp_path / "run", ReActConfig(), progress=False)
    assert summary.ran == 2
    header = read_header(tmp_path / "run")
    assert header.planner == "react" and header.config["thought_tokens"] == 24
    assert header.prompt_version.startswith("react-")
    for record in read_episodes(tmp_path / "run"):
        assert record.plan == ("find an apple", "done")
        assert record.trace["thoughts"] == ["I will act now.", "I will act now."]
