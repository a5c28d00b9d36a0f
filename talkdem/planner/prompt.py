"""The SayCan planner prompt, built from versioned text files in `prompts/`.

Layout (LoTa-Bench's ALFRED prompt, with REI-Bench's labels; every choice and its source is in
docs/strategies.md):

    Robot: Hi there, I'm a robot operating in a home.             <- prompts/saycan_header.txt
    Robot: You can ask me to do various tasks and I'll tell you ...
    Human: <example instruction>                                   <- six task-type examples (LoTa: `Human:`)
    Robot: 1. find an apple, 2. pick up the apple, ..., 5. done.
    [demonstrations of ICL / CARE (intro line, then instruction, interpretation, plan)]
    [strategy preamble (AP's awareness sentence), right before the query as in REI-Bench]
    Human pending instruction: <the instruction>                   <- REI-Bench's label (TOCC: `Human:`)
    [Hint: <CoT's interpretation>]
    Robot: 1.

Each chosen step is appended as ` <skill>, <n>.` (after a failure, with the simulator's message when the
planner shows it: ` <skill> (this action failed: <message>), <n>.`, REI-Bench's wording); a candidate skill is
scored as the continuation ` <skill>` (the separating space belongs to the continuation, as in LoTa-Bench).

`prompt_version()` names the prompt text: VERSION (bumped by hand whenever this module's layout changes),
a hash of every prompt file, and a hash of the rendering settings a run passes (feedback, strategy options).
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from functools import cache
from pathlib import Path

__all__ = [
    "EXAMPLE_PREFIX",
    "HUMAN_PREFIX",
    "Demonstration",
    "append_exchange",
    "append_step",
    "build_prompt",
    "clarify_intro",
    "format_plan",
    "prompt_head",
    "prompt_text",
    "prompt_version",
]

HUMAN_PREFIX = "Human pending instruction: "
"""The query's label (REI-Bench) and the demonstrations' (the paper's ICL and CARE boxes)."""
EXAMPLE_PREFIX = "Human: "
"""The six task-type examples' label (LoTa-Bench's ALFRED prompt, which REI-Bench keeps)."""
_PROMPTS = Path(__file__).parent / "prompts"


@cache
def prompt_text(name: str) -> str:
    """The text of `prompts/<name>.txt`."""
    path = _PROMPTS / f"{name}.txt"
    if not path.is_file():
        raise FileNotFoundError(f"{path}: no such prompt file")
    return path.read_text()


@cache
def _files_version() -> tuple[str, str]:
    digest = hashlib.sha256()
    for path in sorted(_PROMPTS.glob("*.txt")):
        digest.update(path.name.encode() + b"\0" + path.read_bytes())
    return (_PROMPTS / "VERSION").read_text().strip(), digest.hexdigest()[:8]


def prompt_version(settings: Mapping[str, object] | None = None) -> str:
    """`v<VERSION>-<hash of every prompt file>[-<hash of settings>]`.

    `settings`: what a run sets that changes a rendered prompt (failure feedback, strategy options); two runs
    whose prompts can differ never share a version.
    """
    version, files = _files_version()
    name = f"v{version}-{files}"
    if settings:
        blob = json.dumps(settings, sort_keys=True, separators=(",", ":"), default=str)
        name += "-" + hashlib.sha256(blob.encode()).hexdigest()[:8]
    return name


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


def _render(demo: Demonstration, label: str) -> str:
    interpretation = f"{demo.interpretation}\n" if demo.interpretation else ""
    return f"{label}{demo.instruction}\n{interpretation}Robot: {format_plan(demo.plan)}\n"


def _line(label: str, text: str) -> str:
    # An empty text (TOCC's empty rewrite) leaves the bare label: the planner is shown that nothing came.
    return f"{label}{' '.join(text.split())}".rstrip() + "\n"


def prompt_head(
    instruction: str,
    examples: Sequence[Demonstration],
    *,
    preamble: str = "",
    demonstrations: Sequence[Demonstration] = (),
    demonstrations_intro: str = "",
    query_label: str = HUMAN_PREFIX,
) -> str:
    """The planner's context through the query line (what CoT's question follows, as in REI-Bench)."""
    parts = [prompt_text("saycan_header")]
    parts += [_render(example, EXAMPLE_PREFIX) for example in examples]
    if demonstrations:
        parts.append(demonstrations_intro)
        parts += [_render(demo, HUMAN_PREFIX) for demo in demonstrations]
    parts.append(preamble)
    parts.append(_line(query_label, instruction))
    return "".join(parts)


def build_prompt(
    instruction: str,
    examples: Sequence[Demonstration],
    *,
    preamble: str = "",
    demonstrations: Sequence[Demonstration] = (),
    demonstrations_intro: str = "",
    interpretation: str = "",
    query_label: str = HUMAN_PREFIX,
) -> str:
    """The planner's context up to `Robot: 1.` (no trailing space). `interpretation` is a whole line
    (CoT passes `Hint: <sentence>`); an empty one adds no line."""
    head = prompt_head(
        instruction,
        examples,
        preamble=preamble,
        demonstrations=demonstrations,
        demonstrations_intro=demonstrations_intro,
        query_label=query_label,
    )
    if interpretation.strip():
        head += f"{' '.join(interpretation.split())}\n"
    return head + "Robot: 1."


def append_step(context: str, skill: str, next_index: int, failure: str = "") -> str:
    """The context after executing `skill`: ` <skill>, <n>.`, or with a failure message to show,
    ` <skill> (this action failed: <message>), <n>.` (REI-Bench's and LoTa-Bench's wording)."""
    shown = f" (this action failed: {' '.join(failure.split()).lower()})" if failure.strip() else ""
    return f"{context} {skill}{shown}, {next_index}."


def clarify_intro(questions: Sequence[str], budget: int) -> str:
    """The line that tells the planner, in clarification mode, which questions it may ask (before the query,
    where a strategy's preamble goes; kept in code, not a prompt file, so that runs without clarification keep
    their prompt version and input hashes)."""
    listed = "; ".join(questions)
    return (
        f"Robot: When a request is unclear, I can first ask you at most {budget} question(s), one per step: {listed}.\n"
    )


def append_exchange(context: str, question: str, answer: str) -> str:
    """The context after a question and its answer: the current `Robot:` line is closed, the question and
    answer follow as dialogue lines, and the steps so far are listed again on a new `Robot:` line (so the next
    step is scored after the same kind of numbered list as every other step):

        Robot: 1. find an apple, 2.   ->   Robot: 1. find an apple.
                                           Robot: ask where to put it
                                           Person: In the fridge.
                                           Robot: 1. find an apple, 2.
    """
    head, marker, listing = context.rpartition("\nRobot: ")
    if not marker:
        raise ValueError("a planner context ends with a 'Robot:' line")
    done, _, current = listing.rpartition(" ")
    if not current.endswith(".") or not current[:-1].isdigit():
        raise ValueError(f"a planner context ends with the next step's number, not {current!r}")
    done = done.rstrip(",")
    closed = f"{marker}{done}." if done else ""
    restated = f"{done}, {current}" if done else current
    spoken = " ".join(answer.split())
    return f"{head}{closed}{marker}{' '.join(question.split())}\nPerson: {spoken}{marker}{restated}"
