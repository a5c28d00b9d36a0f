"""Mitigation strategies: what the planner is shown for an instruction (paper, appendix "Mitigation Methods").

A strategy turns a batch of instructions into `PlannerInput`s; strategies that need the model's words
first (CoT's interpretation, TOCC's rewrite) send one batch of generation requests. Registered by name
as `module:Class` and imported lazily (CARE lives in the top-level `care/` package).
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from typing import ClassVar

from talkdem.instructions import MemoryItem, load_memory_bank
from talkdem.llm.interface.base import LanguageModel
from talkdem.llm.interface.options import BackendOption, OptionValue, parse_options
from talkdem.planner.decoding import MAX_NEW_TOKENS, StepDecoding
from talkdem.planner.examples import task_type_examples
from talkdem.planner.prompt import EXAMPLE_PREFIX, HUMAN_PREFIX, Demonstration, prompt_head, prompt_text
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
    "strategies_with_option",
    "strategy_args",
    "strategy_options",
]


@dataclass(frozen=True)
class PlannerInput:
    """What the SayCan prompt is built from for one instruction."""

    instruction: str
    """The instruction the planner sees (TOCC: the rewrite, possibly empty; otherwise the original)."""
    preamble: str = ""
    """Lines right before the query (AP's awareness sentence)."""
    demonstrations: tuple[Demonstration, ...] = ()
    demonstrations_intro: str = ""
    interpretation: str = ""
    """A line after the instruction (CoT: `Hint: <the model's one-sentence task>`)."""
    query_label: str = HUMAN_PREFIX
    notes: dict[str, str] = field(default_factory=dict)
    """Intermediate outputs worth recording in the episode (the rewrite and its status, the interpretation,
    retrieved ids)."""


class Strategy(ABC):
    name: str
    arguments: ClassVar[tuple[BackendOption, ...]] = ()
    """The constructor options a user may set (`--strategy-arg KEY=VALUE`, a sweep strategy's `args:`), declared
    as backends declare theirs: each names a keyword of the constructor and the type its text is parsed to."""

    @abstractmethod
    def prepare(self, instructions: Sequence[str], model: LanguageModel) -> list[PlannerInput]:
        """One `PlannerInput` per instruction, in order."""

    def options(self) -> dict[str, object]:
        """The constructor arguments that change what the planner is shown (`config.strategy_args`)."""
        return {}


class Vanilla(Strategy):
    """The planner prompt alone."""

    name = "vanilla"

    def prepare(self, instructions: Sequence[str], model: LanguageModel) -> list[PlannerInput]:
        return [PlannerInput(instruction) for instruction in instructions]


class AwarePrompt(Strategy):
    """AP: an awareness sentence (a `Robot:` line) right before the query, where REI-Bench puts it."""

    name = "ap"

    def prepare(self, instructions: Sequence[str], model: LanguageModel) -> list[PlannerInput]:
        preamble = prompt_text("aware")
        return [PlannerInput(instruction, preamble=preamble) for instruction in instructions]


def _decoding(max_new_tokens: int, chat: bool) -> StepDecoding:
    return StepDecoding(max_new_tokens=max_new_tokens, chat=chat)


_GENERATION_ARGUMENTS = (
    BackendOption("max_new_tokens", "int", "token budget of the generated text (default: measured)", minimum=1),
    BackendOption("chat", "bool", "false: continue the prompt as plain text, as REI-Bench does"),
)
"""CoT's and TOCC's options: the names their header records (`config.strategy_args`)."""


class ChainOfThought(Strategy):
    """CoT (REI-Bench's CoT with the paper's question): the SayCan prompt through the query, then the
    question; the answer goes after the query as `Hint: <answer>`, the original instruction stays."""

    name = "cot"
    arguments = _GENERATION_ARGUMENTS

    def __init__(self, max_new_tokens: int = MAX_NEW_TOKENS, chat: bool = True) -> None:
        self.decoding = _decoding(max_new_tokens, chat)

    def options(self) -> dict[str, object]:
        return self.decoding.options()

    def prepare(self, instructions: Sequence[str], model: LanguageModel) -> list[PlannerInput]:
        examples = task_type_examples()
        question = prompt_text("cot")
        prompts = [prompt_head(i, examples) + question for i in instructions]
        inputs = []
        for instruction, answer in zip(instructions, self.decoding.run(model, prompts), strict=True):
            # An empty answer adds no line: the planner sees the Vanilla prompt, and the status says so.
            hint = f"Hint: {answer.text}" if answer.text else ""
            notes = {"interpretation": answer.text, "interpretation_status": answer.status}
            inputs.append(PlannerInput(instruction, interpretation=hint, notes=notes))
        return inputs


class TaskOrientedContextCognition(Strategy):
    """TOCC: rewrite the instruction into one clear instruction (standalone prompt, as in REI-Bench); the
    planner sees only the rewrite, labelled `Human:` as REI-Bench does, and never the original."""

    name = "tocc"
    arguments = _GENERATION_ARGUMENTS

    def __init__(self, max_new_tokens: int = MAX_NEW_TOKENS, chat: bool = True) -> None:
        self.decoding = _decoding(max_new_tokens, chat)

    def options(self) -> dict[str, object]:
        return self.decoding.options()

    def prepare(self, instructions: Sequence[str], model: LanguageModel) -> list[PlannerInput]:
        template = prompt_text("tocc")
        rewrites = self.decoding.run(model, [template.format(query=" ".join(i.split())) for i in instructions])
        # The paper: "the planner did not receive the original instruction". An empty rewrite is shown as
        # an empty query (status `empty`), never replaced by the original.
        return [
            PlannerInput(r.text, query_label=EXAMPLE_PREFIX, notes={"rewrite": r.text, "rewrite_status": r.status})
            for r in rewrites
        ]


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


def load_strategy(name: str, **options: object) -> Strategy:
    """Instantiate a registered strategy with its options; unknown names get a did-you-mean."""
    return STRATEGIES.create(name, **options)


def strategy_options(name: str) -> tuple[BackendOption, ...]:
    """The options strategy `name` declares (its class's module is imported, as a run of it would)."""
    declared: tuple[BackendOption, ...] = getattr(STRATEGIES.factory(name), "arguments", ())
    return declared


def strategies_with_option(key: str) -> tuple[str, ...]:
    """The strategies that declare option `key`, in registration order."""
    return tuple(s for s in STRATEGIES.names() if any(o.name == key for o in strategy_options(s)))


def strategy_args(name: str, items: Iterable[str]) -> dict[str, OptionValue]:
    """`KEY=VALUE` strings as strategy `name`'s typed constructor options; ValueError, one line naming the key, for
    a bad value, a key no strategy has (listing `name`'s keys) or a key of another strategy (naming those)."""
    items = list(items)
    if not items:
        return {}  # no strategy module is imported for nothing
    return parse_options(
        strategy_options(name),
        items,
        owner=f"the {name} strategy",
        what="strategy arg",
        flag="--strategy-arg",
        elsewhere=lambda key: [other for other in strategies_with_option(key) if other != name],
    )
