"""Mitigation strategies: what the planner is shown for an instruction (paper, appendix "Mitigation Methods").

A strategy turns a batch of instructions into `PlannerInput`s; strategies that need the model's words
first (CoT's interpretation, TOCC's rewrite) send one batch of generation requests. Registered by name
as `module:Class` and imported lazily (CARE lives in the top-level `care/` package).
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Sequence
from dataclasses import dataclass, field

from talkdem.instructions import MemoryItem, load_memory_bank
from talkdem.llm.base import LanguageModel
from talkdem.llm.requests import GenerateRequest
from talkdem.planner.prompt import Demonstration, prompt_text
from talkdem.registry import Registry
from talkdem.schema import PATTERN_CONFIGS

__all__ = [
    "STRATEGIES",
    "AwarePrompt",
    "ChainOfThought",
    "InContextLearning",
    "PlannerInput",
    "Strategy",
    "TaskOrientedContextCognition",
    "Vanilla",
    "fixed_icl_demonstrations",
    "load_strategy",
]


@dataclass(frozen=True)
class PlannerInput:
    """What the SayCan prompt is built from for one instruction."""

    instruction: str
    """The instruction the planner sees (TOCC: the rewrite; otherwise the original)."""
    preamble: str = ""
    demonstrations: tuple[Demonstration, ...] = ()
    demonstrations_intro: str = ""
    interpretation: str = ""
    """A line after the instruction (CoT: the model's one-sentence task)."""
    notes: dict[str, str] = field(default_factory=dict)
    """Intermediate outputs worth recording in the episode (the rewrite, the interpretation, retrieved ids)."""


class Strategy(ABC):
    name: str

    @abstractmethod
    def prepare(self, instructions: Sequence[str], model: LanguageModel) -> list[PlannerInput]:
        """One `PlannerInput` per instruction, in order."""


class Vanilla(Strategy):
    """The planner prompt alone."""

    name = "vanilla"

    def prepare(self, instructions: Sequence[str], model: LanguageModel) -> list[PlannerInput]:
        return [PlannerInput(instruction) for instruction in instructions]


class AwarePrompt(Strategy):
    """AP: an awareness sentence warns that the instruction may be irregular."""

    name = "ap"

    def prepare(self, instructions: Sequence[str], model: LanguageModel) -> list[PlannerInput]:
        preamble = prompt_text("aware")
        return [PlannerInput(instruction, preamble=preamble) for instruction in instructions]


class ChainOfThought(Strategy):
    """CoT: first ask for the single household task in one sentence, then plan with it added."""

    name = "cot"

    def prepare(self, instructions: Sequence[str], model: LanguageModel) -> list[PlannerInput]:
        template = prompt_text("cot")
        answers = model.generate([GenerateRequest(template.format(query=i), max_new_tokens=48) for i in instructions])
        return [
            PlannerInput(instruction, interpretation=answer, notes={"interpretation": answer})
            for instruction, answer in zip(instructions, answers, strict=True)
        ]


class TaskOrientedContextCognition(Strategy):
    """TOCC: rewrite the instruction into one clear instruction; the planner sees only the rewrite."""

    name = "tocc"

    def prepare(self, instructions: Sequence[str], model: LanguageModel) -> list[PlannerInput]:
        template = prompt_text("tocc")
        rewrites = model.generate([GenerateRequest(template.format(query=i), max_new_tokens=48) for i in instructions])
        inputs = []
        for instruction, rewrite in zip(instructions, rewrites, strict=True):
            # An empty rewrite would leave the planner with nothing: fall back to the original, and say so.
            shown = rewrite or instruction
            inputs.append(PlannerInput(shown, notes={"rewrite": rewrite, "rewrite_empty": str(not rewrite)}))
        return inputs


def fixed_icl_demonstrations(memory: Sequence[MemoryItem]) -> tuple[Demonstration, ...]:
    """Five fixed resolved examples, one per pattern, from memory-bank tasks of five different task types.

    Rule: patterns in the dataset's order; for each, the level-2 item (a middle intensity) of the first
    memory task (by id) whose task type is not used yet.
    """
    chosen: list[Demonstration] = []
    used_types: set[str] = set()
    for pattern in PATTERN_CONFIGS:
        candidates = sorted(
            (m for m in memory if m.condition.pattern == pattern and m.condition.level == 2),
            key=lambda m: m.task_id,
        )
        pick = next((m for m in candidates if m.task_type not in used_types), None)
        if pick is None:
            raise ValueError(f"the memory bank has no level-2 item of pattern '{pattern}' for a new task type")
        used_types.add(pick.task_type)
        chosen.append(Demonstration(pick.instruction, pick.reference_plan, pick.interpretation))
    return tuple(chosen)


class InContextLearning(Strategy):
    """ICL: five fixed resolved examples (instruction, interpretation, plan), one per pattern."""

    name = "icl"

    def __init__(self, memory: Sequence[MemoryItem] | None = None) -> None:
        self.demonstrations = fixed_icl_demonstrations(memory if memory is not None else load_memory_bank())

    def prepare(self, instructions: Sequence[str], model: LanguageModel) -> list[PlannerInput]:
        intro = prompt_text("demonstrations_intro")
        return [
            PlannerInput(instruction, demonstrations=self.demonstrations, demonstrations_intro=intro)
            for instruction in instructions
        ]


# The paper's order; labels are what tables, plots and the leaderboard show. CARE lives in the top-level
# `care/` package, which imports this module: registering it by name keeps the dependency one-way.
STRATEGIES: Registry[Strategy] = Registry("strategy")
STRATEGIES.register("vanilla", Vanilla, "Vanilla")
STRATEGIES.register("ap", AwarePrompt, "AP")
STRATEGIES.register("cot", ChainOfThought, "CoT")
STRATEGIES.register("icl", InContextLearning, "ICL")
STRATEGIES.register("tocc", TaskOrientedContextCognition, "TOCC")
STRATEGIES.register("care", "care.strategy:ContextAwareRetrieval", "CARE")


def load_strategy(name: str) -> Strategy:
    """Instantiate a registered strategy; unknown names get a did-you-mean."""
    return STRATEGIES.create(name)
