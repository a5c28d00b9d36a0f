"""The SayCan planner prompt, built from versioned text files in `prompts/`.

Layout (LoTa-Bench / REI-Bench style):

    Robot: Hi there, I'm a robot operating in a house.            <- prompts/saycan_header.txt
    Robot: You can ask me to do various tasks ...
    [strategy preamble, e.g. the AP awareness sentence]
    Human pending instruction: <example instruction>              <- six task-type examples
    Robot: 1. find an apple, 2. pick up the apple, ..., 5. done.
    [demonstrations of ICL / CARE: instruction, interpretation, plan]
    Human pending instruction: <the instruction>
    [interpretation line (CoT)]
    Robot: 1.

Each chosen step is appended as ` <skill>, <n>.`; a candidate skill is scored as the continuation
` <skill>` (the separating space belongs to the continuation, as in lm-evaluation-harness).
"""

from __future__ import annotations

import hashlib
from collections.abc import Sequence
from dataclasses import dataclass
from functools import cache
from pathlib import Path

__all__ = [
    "HUMAN_PREFIX",
    "Demonstration",
    "append_step",
    "build_prompt",
    "format_plan",
    "prompt_text",
    "prompt_version",
]

HUMAN_PREFIX = "Human pending instruction: "
_PROMPTS = Path(__file__).parent / "prompts"


@cache
def prompt_text(name: str) -> str:
    """The text of `prompts/<name>.txt`."""
    path = _PROMPTS / f"{name}.txt"
    if not path.is_file():
        raise FileNotFoundError(f"{path}: no such prompt file")
    return path.read_text()


@cache
def prompt_version() -> str:
    """`v<VERSION>-<hash of every prompt file>`: changes whenever any prompt text changes."""
    digest = hashlib.sha256()
    for path in sorted(_PROMPTS.glob("*.txt")):
        digest.update(path.name.encode() + b"\0" + path.read_bytes())
    return f"v{(_PROMPTS / 'VERSION').read_text().strip()}-{digest.hexdigest()[:8]}"


@dataclass(frozen=True)
class Demonstration:
    """A solved example shown in the prompt."""

    instruction: str
    plan: tuple[str, ...]
    interpretation: str = ""
    """One sentence stating the task (ICL and CARE demonstrations have one; task-type examples do not)."""


def format_plan(plan: Sequence[str]) -> str:
    """`1. find an apple, 2. pick up the apple, 3. done.`"""
    return ", ".join(f"{i}. {skill}" for i, skill in enumerate(plan, start=1)) + "."


def _render(demo: Demonstration) -> str:
    interpretation = f"{demo.interpretation}\n" if demo.interpretation else ""
    return f"{HUMAN_PREFIX}{demo.instruction}\n{interpretation}Robot: {format_plan(demo.plan)}\n"


def build_prompt(
    instruction: str,
    examples: Sequence[Demonstration],
    *,
    preamble: str = "",
    demonstrations: Sequence[Demonstration] = (),
    demonstrations_intro: str = "",
    interpretation: str = "",
) -> str:
    """The planner's context up to `Robot: 1.` (no trailing space)."""
    parts = [prompt_text("saycan_header"), preamble]
    parts += [_render(example) for example in examples]
    if demonstrations:
        parts.append(demonstrations_intro)
        parts += [_render(demo) for demo in demonstrations]
    query = f"{HUMAN_PREFIX}{' '.join(instruction.split())}\n"
    if interpretation:
        query += f"{' '.join(interpretation.split())}\n"
    parts.append(query + "Robot: 1.")
    return "".join(parts)


def append_step(context: str, skill: str, next_index: int) -> str:
    """The context after executing `skill`: ` <skill>, <n>.`"""
    return f"{context} {skill}, {next_index}."
