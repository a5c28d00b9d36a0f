"""The dataset's vocabulary, declared once: patterns (names, abbreviations, level definitions), levels, the
clean control, conditions with parsing and instruction-id round trips, task types, the config -> split ->
file layout, and the features.

Everything that names a pattern, a level or a condition imports it from here: the dataset builders, the
loader (`talk_dem`), the planner's episode sampling, the metrics, reports and leaderboard. The module is light:
`datasets` is imported only when the features are asked for.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Literal

if TYPE_CHECKING:
    import datasets

__all__ = [
    "ALL",
    "CLEAN",
    "CLEAN_CONDITION",
    "CONDITIONS",
    "CONFIGS",
    "LEVELS",
    "MEMORY_BANK",
    "PATTERNS",
    "PATTERN_CONFIGS",
    "TASKS",
    "TASK_TYPES",
    "Condition",
    "Pattern",
    "canonical_instruction_id",
    "data_files",
    "default_split",
    "features",
    "parse_conditions",
    "parse_instruction_id",
    "split_name",
]


@dataclass(frozen=True)
class Pattern:
    """One dementia-associated communication pattern (paper, section "Communication Patterns")."""

    config: str
    """Config name on the Hub (snake_case)."""
    name: str
    abbreviation: str
    definition: str
    levels: dict[int, str]
    """What intensity 1, 2 and 3 mean for this pattern."""


PATTERNS: dict[str, Pattern] = {
    p.config: p
    for p in (
        Pattern(
            "referential_imprecision",
            "Referential Imprecision",
            "RI",
            "The intended object is first referred to by a vague or nonspecific expression; its identity is "
            "clarified later or conveyed through circumlocution.",
            {
                1: "A vague expression at the first reference to the target, immediately followed by the "
                "object name as a brief self-clarification (same phrase).",
                2: "The vague expression stands in the request; the name comes only later, after the rest "
                "of the request (a later phrase or sentence).",
                3: "Circumlocution: several vague references and a description of the object (its use or "
                "look) stand in for the name, which is found only at the end after word-finding trouble.",
            },
        ),
        Pattern(
            "object_substitution",
            "Object Substitution",
            "OS",
            "The intended object is first replaced by an incorrect but plausible object from the same scene; "
            "the selection is revised later in the utterance.",
            {
                1: "A competing in-scene object, corrected at once within the same phrase.",
                2: "The competing object stays in the whole request; the correction comes afterwards.",
                3: "Repeated substitution: two wrong in-scene objects (or one kept through two attempts) and "
                "two or more self-corrections before the target is settled.",
            },
        ),
        Pattern(
            "empty_speech",
            "Empty Speech",
            "ES",
            "Task information is interrupted by semantically non-informative speech (fillers, stock phrases, "
            "empty clauses), so the instruction is dispersed across the utterance.",
            {
                1: "One empty expression inside the request.",
                2: "Two or more empty expressions inside the request, three or more in all.",
                3: "Empty speech between most task phrases and around the request: three or more inside, "
                "five or more in all, including whole empty sentences.",
            },
        ),
        Pattern(
            "topic_drift",
            "Topic Drift",
            "TD",
            "The complete instruction is followed by off-task associations that move progressively away from "
            "the task and bring in other objects of the scene.",
            {
                1: "One associated remark about another object in the scene.",
                2: "Two sentences drifting from a scene object to a personal memory, two scene objects.",
                3: "Four or more sentences drifting from the scene through memories to unrelated topics, "
                "three or more scene objects.",
            },
        ),
        Pattern(
            "intrusion",
            "Intrusion",
            "IN",
            "The instruction is interrupted by an off-task thought before it is complete; the remaining task "
            "information is resumed afterwards.",
            {
                1: "One short off-task question or remark breaks into the request, which then resumes.",
                2: "A longer intrusion (two sentences) before the request resumes.",
                3: "Two intrusions of short fragmented sentences; the resumption restates part of the request.",
            },
        ),
    )
}

PATTERN_CONFIGS: tuple[str, ...] = tuple(PATTERNS)
"""The five pattern config names, in the paper's order."""

LEVELS = (1, 2, 3)
"""Intensity levels of every pattern (the clean control is level 0)."""

CLEAN = "clean"
ALL = "all"
MEMORY_BANK = "memory_bank"
TASKS = "tasks"

CONFIGS = (*PATTERN_CONFIGS, CLEAN, ALL, MEMORY_BANK, TASKS)
"""Every config of the dataset: one per pattern (splits level_1..level_3), clean, all (the 4,800 instructions
in one split), memory_bank, tasks."""

TASK_TYPES = (
    "look_at_obj_in_light",
    "pick_and_place_simple",
    "pick_and_place_with_movable_recep",
    "pick_clean_then_place_in_recep",
    "pick_cool_then_place_in_recep",
    "pick_heat_then_place_in_recep",
)
"""The six ALFRED task types (class labels of `task_type`, in this order)."""


# --- conditions -------------------------------------------------------------------------------------------------
@dataclass(frozen=True, order=True)
class Condition:
    """A pattern at an intensity level, or the clean control (`clean`, level 0)."""

    pattern: str
    level: int = 0

    def __str__(self) -> str:
        return self.pattern if self.pattern == CLEAN else f"{self.pattern}:{self.level}"

    @property
    def is_clean(self) -> bool:
        return self.pattern == CLEAN

    def instruction_id(self, task_id: str) -> str:
        """`<task>:clean:0` or `<task>:<pattern>:<level>` (the inverse of `parse_instruction_id`)."""
        return f"{task_id}:{self.pattern}:{self.level}"

    @classmethod
    def parse(cls, text: str) -> Condition:
        """`clean`, `intrusion:3` (a pattern alone is expanded to its three levels by `parse_conditions`)."""
        name, colon, level = text.strip().partition(":")
        if name != CLEAN and name not in PATTERNS:
            raise ValueError(f"unknown condition '{text}': expected clean or one of {', '.join(PATTERNS)}")
        if name == CLEAN:
            # `clean:0` is how instruction ids spell the control; any other level would be dropped without a word
            if colon and level != "0":
                raise ValueError(f"condition '{text}': clean has no levels (write clean)")
            return cls(CLEAN, 0)
        if level not in {str(n) for n in LEVELS}:
            raise ValueError(f"condition '{text}': the level must be 1, 2 or 3")
        return cls(name, int(level))


CLEAN_CONDITION = Condition(CLEAN, 0)
CONDITIONS: tuple[Condition, ...] = (
    CLEAN_CONDITION,
    *(Condition(pattern, level) for pattern in PATTERN_CONFIGS for level in LEVELS),
)
"""The 16 conditions of every task: the clean control, then each pattern by level."""


def parse_conditions(text: str | None) -> tuple[Condition, ...]:
    """`clean,intrusion:3,topic_drift` -> conditions (a pattern without a level means all three); None: all 16.
    A condition named twice (`clean,clean`, `intrusion,intrusion:3`) is selected once, and empty parts
    (`clean,`) are skipped; a text with no condition at all is refused."""
    if text is None:
        return CONDITIONS
    conditions: list[Condition] = []
    for part in (p.strip() for p in text.split(",")):
        if not part:
            continue
        if part != CLEAN and ":" not in part:
            if part not in PATTERNS:  # named as written, not as the `part:1` it would expand to
                raise ValueError(f"unknown condition '{part}': expected clean or one of {', '.join(PATTERNS)}")
            conditions += [Condition(part, level) for level in LEVELS]
        else:
            conditions.append(Condition.parse(part))
    if not conditions:
        raise ValueError(f"no condition in '{text}': expected e.g. clean,intrusion:3,topic_drift")
    return tuple(dict.fromkeys(conditions))


def parse_instruction_id(instruction_id: str) -> tuple[str, Condition]:
    """`<task>:clean`, `<task>:clean:0` or `<task>:<pattern>:<level>` -> (task id, condition); a
    ValueError saying what an id looks like otherwise."""
    parts = instruction_id.split(":") if isinstance(instruction_id, str) else []
    if len(parts) in (2, 3) and parts[0] and parts[1] == CLEAN and (len(parts) == 2 or parts[2] == "0"):
        return parts[0], CLEAN_CONDITION
    if len(parts) == 3 and parts[0] and parts[1] in PATTERNS and parts[2] in {str(n) for n in LEVELS}:
        return parts[0], Condition(parts[1], int(parts[2]))
    raise ValueError(f"'{instruction_id}' is not an instruction id (<task_id>:clean or <task_id>:<pattern>:<level>)")


def canonical_instruction_id(instruction_id: str) -> str:
    """The id as the dataset stores it: `<task>:clean`, the clean instruction's short form, is `<task>:clean:0`;
    every other id is its own canonical form. A ValueError (`parse_instruction_id`'s) for what is no id."""
    task_id, condition = parse_instruction_id(instruction_id)
    return condition.instruction_id(task_id)


# --- the file layout --------------------------------------------------------------------------------------------
def split_name(level: int) -> str:
    return f"level_{level}"


def data_files(config: str) -> dict[str, tuple[str, ...]]:
    """split -> Parquet files (relative to the dataset folder) of `config`: what the card declares, the build
    writes and the loader reads."""
    if config in PATTERNS:
        return {split_name(level): (f"{config}/{split_name(level)}.parquet",) for level in LEVELS}
    if config == CLEAN:
        return {"test": ("clean/test.parquet",)}
    if config == ALL:
        everything = [f for c in (CLEAN, *PATTERN_CONFIGS) for files in data_files(c).values() for f in files]
        return {"test": tuple(everything)}
    if config == MEMORY_BANK:
        return {"train": ("memory_bank/train.parquet",)}
    if config == TASKS:
        return {"benchmark": ("tasks/benchmark.parquet",), "memory": ("tasks/memory.parquet",)}
    raise ValueError(f"unknown config '{config}': expected one of {', '.join(CONFIGS)}")


def default_split(config: str) -> str:
    """The split a config loads when none is named (the first one declared)."""
    return next(iter(data_files(config)))


# --- features ---------------------------------------------------------------------------------------------------
FeatureKind = Literal["instruction", "memory_bank", "task"]


def features(kind: FeatureKind) -> datasets.Features:
    """The `datasets` features of one row kind: `instruction` (clean, all and the pattern configs),
    `memory_bank` (an instruction plus its gold interpretation and reference plan), `task`."""
    import datasets

    string = datasets.Value("string")
    pddl = {
        "object_target": string,
        "parent_target": string,
        "mrecep_target": string,
        "toggle_target": string,
        "object_sliced": datasets.Value("bool"),
    }
    task_type = datasets.ClassLabel(names=list(TASK_TYPES))
    if kind == "task":
        return datasets.Features(
            {
                "task_id": string,
                "task_set": string,
                "task_type": task_type,
                "task_name": string,
                "floor_plan": string,
                "seed_instruction": string,
                "interpretation": string,
                "pddl_params": pddl,
                "scene_objects": datasets.List(string),
                "reference_plan": datasets.List(string),
            }
        )
    instruction = {
        "id": string,
        "task_id": string,
        "task_type": task_type,
        "pattern": datasets.ClassLabel(names=[CLEAN, *PATTERN_CONFIGS]),
        "level": datasets.Value("int32"),
        "instruction": string,
        "clean_instruction": string,
        "seed_instruction": string,
        "pddl_params": pddl,
        "floor_plan": string,
        "scene_objects": datasets.List(string),
        "verification": {
            "passed": datasets.Value("bool"),
            "failed_checks": datasets.List(string),
            "attempts": datasets.Value("int32"),
        },
        "generator": string,
        "prompt_version": string,
        "seed": datasets.Value("int64"),
        "ranking": {
            "score": datasets.Value("float64"),
            "model": string,
            "candidates": datasets.Value("int32"),
            "passed": datasets.Value("int32"),
            "scored": datasets.List({"seed": datasets.Value("int64"), "score": datasets.Value("float64")}),
        },
    }
    if kind == "instruction":
        return datasets.Features(instruction)
    if kind == "memory_bank":
        return datasets.Features({**instruction, "interpretation": string, "reference_plan": datasets.List(string)})
    raise ValueError(f"unknown row kind '{kind}': expected instruction, memory_bank or task")
