"""TALK-Dem: the single declaration of the dataset's patterns, levels and schema, and a one-call loader.

The dataset folder (`data/` here, or the Hub repository) loads with `datasets` alone, through the YAML
`configs` of its README.md; this module is a convenience and the source the build writes the schema from.
It deliberately lives outside the dataset folder: `datasets` refuses a folder `foo/` holding `foo.py`.

    >>> import talk_dem
    >>> talk_dem.load("topic_drift", 3)          # doctest: +SKIP
    Dataset({features: [...], num_rows: 300})
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import datasets

__all__ = [
    "CLEAN",
    "CONFIGS",
    "INSTRUCTION_FEATURES",
    "LEVELS",
    "MEMORY_BANK_FEATURES",
    "PATTERNS",
    "TASK_FEATURES",
    "TASK_TYPES",
    "Pattern",
    "load",
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

LEVELS = (1, 2, 3)
CLEAN = "clean"
ALL = "all"
CONFIGS = (*PATTERNS, CLEAN, ALL, "memory_bank", "tasks")
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

_PATTERN_LABEL = datasets.ClassLabel(names=[CLEAN, *PATTERNS])
_TASK_TYPE_LABEL = datasets.ClassLabel(names=list(TASK_TYPES))


def split_name(level: int) -> str:
    return f"level_{level}"


_PDDL = {
    "object_target": datasets.Value("string"),
    "parent_target": datasets.Value("string"),
    "mrecep_target": datasets.Value("string"),
    "toggle_target": datasets.Value("string"),
    "object_sliced": datasets.Value("bool"),
}
_VERIFICATION = {
    "passed": datasets.Value("bool"),
    "failed_checks": datasets.List(datasets.Value("string")),
    "attempts": datasets.Value("int32"),
}

INSTRUCTION_FEATURES = datasets.Features(
    {
        "id": datasets.Value("string"),
        "task_id": datasets.Value("string"),
        "task_type": _TASK_TYPE_LABEL,
        "pattern": _PATTERN_LABEL,
        "level": datasets.Value("int32"),
        "instruction": datasets.Value("string"),
        "clean_instruction": datasets.Value("string"),
        "seed_instruction": datasets.Value("string"),
        "pddl_params": _PDDL,
        "floor_plan": datasets.Value("string"),
        "scene_objects": datasets.List(datasets.Value("string")),
        "verification": _VERIFICATION,
        "generator": datasets.Value("string"),
        "prompt_version": datasets.Value("string"),
        "seed": datasets.Value("int64"),
    }
)
"""One instruction (clean control or pattern variant) of the 300 benchmark tasks."""

MEMORY_BANK_FEATURES = datasets.Features(
    {
        **INSTRUCTION_FEATURES,
        "interpretation": datasets.Value("string"),
        "reference_plan": datasets.List(datasets.Value("string")),
    }
)
"""One CARE memory item: an instruction of a held-out task, its gold interpretation and reference plan."""

TASK_FEATURES = datasets.Features(
    {
        "task_id": datasets.Value("string"),
        "task_set": datasets.Value("string"),
        "task_type": _TASK_TYPE_LABEL,
        "task_name": datasets.Value("string"),
        "floor_plan": datasets.Value("string"),
        "seed_instruction": datasets.Value("string"),
        "interpretation": datasets.Value("string"),
        "pddl_params": _PDDL,
        "scene_objects": datasets.List(datasets.Value("string")),
        "reference_plan": datasets.List(datasets.Value("string")),
    }
)
"""Task metadata: the seed, its parameters, the scene's object types and the reference plan."""


def _default_folder() -> str:
    from talkdem.paths import data_dir  # the checkout's data/, $TALKDEM_DATA_DIR, or the wheel's copy

    return str(data_dir())


_DEFAULT_SPLITS = {CLEAN: "test", ALL: "test", "memory_bank": "train", "tasks": "benchmark"}


def load(
    pattern: str, level: int | None = None, *, split: str | None = None, path: str | None = None, **kwargs: Any
) -> datasets.Dataset:
    """One split: `load("intrusion", 2)`, `load("clean")`, `load("memory_bank")`, `load("tasks")`,
    `load("tasks", split="memory")`.

    `path` is a dataset folder or a Hub repository id (`ORG/talk-dem`; read from the Hugging Face cache
    when offline). The default is the dataset this package carries: `data/` of a checkout, the copy in
    the installed wheel, or `$TALKDEM_DATA_DIR`. Other keyword arguments go to `datasets.load_dataset`.
    The clean control is level 0 in episode ids (`<task>:clean:0`), so `load("clean", 0)` is accepted.
    """
    if pattern in PATTERNS:
        if level not in LEVELS:
            raise ValueError(f"pattern '{pattern}' needs a level in {LEVELS}, got {level}")
        chosen = split_name(level)
    elif pattern in _DEFAULT_SPLITS:
        if level not in (None, 0) or (level == 0 and pattern != CLEAN):
            raise ValueError(f"config '{pattern}' has no levels")
        chosen = _DEFAULT_SPLITS[pattern]
    else:
        raise ValueError(f"unknown config '{pattern}': expected one of {', '.join(CONFIGS)}")
    if split is not None and pattern in PATTERNS and split != chosen:
        raise ValueError(f"give either a level or a split for '{pattern}', not both ({level} vs '{split}')")
    source = path or _default_folder()
    if path and not Path(path).exists() and path.count("/") != 1:
        raise ValueError(f"'{path}' is neither a dataset folder nor a Hub repository id (ORG/NAME)")
    result = datasets.load_dataset(source, pattern, split=split or chosen, **kwargs)
    assert isinstance(result, datasets.Dataset)
    return result
