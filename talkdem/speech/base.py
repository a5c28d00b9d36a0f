"""The generator interface: requests as data, one batched call; the registry of generators by name.

A generator turns `GenerationRequest`s into utterances. The build collects every request of a task
(the clean control, then the fifteen pattern variants, then any regenerations) and calls the generator
once per batch, so an LLM backend can batch them and the rules generator simply loops. The simulated person
of the clarification track (`talkdem.clarify.person`) speaks its in-pattern answers through the same call.

The registry knows the rule-based generators, which need no model. The LLM generator is a dataset builder
(`builders/generation/llm.py`) and registers itself here when `builders.generation` is imported, so that only
the dataset-building commands reach it.
"""

from __future__ import annotations

import hashlib
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Protocol

from talkdem.registry import Registry, UnknownNameError
from talkdem.schema import CLEAN
from talkdem.tasks import Task

__all__ = [
    "CLEAN",
    "CURRENT_GENERATOR",
    "RETIRED",
    "Generated",
    "GenerationRequest",
    "Generator",
    "check_generator_name",
    "derive_seed",
    "generate_checked",
    "get_generator",
    "register_generator",
]


@dataclass(frozen=True)
class GenerationRequest:
    """One utterance to produce."""

    task: Task
    pattern: str
    """`clean` (conversationalize the seed) or a pattern config name, e.g. `topic_drift`."""
    level: int
    """1-3 for a pattern; 0 for `clean`."""
    clean: str
    """The clean control to transform (empty for a `clean` request)."""
    seed: int
    """Per-request seed: the same seed gives the same utterance."""
    attempt: int = 1
    """1 for the first generation; 2 and 3 for regenerations after a failed verification."""


class Generator(Protocol):
    """Anything that writes utterances for requests."""

    name: str
    """Registry name, stored with every row (`rules`, `llm`)."""

    @property
    def prompt_version(self) -> str:
        """Version of the prompts or phrase banks behind the output, stored with every row."""
        ...

    def generate(self, requests: Sequence[GenerationRequest]) -> list[str]: ...


@dataclass(frozen=True)
class Generated:
    """One utterance and what the generator itself found wrong with it (before verification)."""

    text: str
    failures: tuple[str, ...] = ()
    """Failure reasons the verifier cannot see, e.g. `unparsable_output` (no valid structured answer) or
    `echo_of_prompt`; a non-empty tuple fails the utterance whatever the verifier says."""
    utterance: bool = True
    """False when `text` is no utterance but a raw answer kept for inspection (an unparsable one): the
    verifier is not run on it, its failures are the generator's alone."""


def generate_checked(generator: Generator, requests: Sequence[GenerationRequest]) -> list[Generated]:
    """`generator.generate_checked` when it has one (the LLM generator: its unparsable or echoed outputs), else
    its plain texts with no failures of their own."""
    checked = getattr(generator, "generate_checked", None)
    if checked is not None:
        results: list[Generated] = checked(requests)
        return results
    return [Generated(text) for text in generator.generate(requests)]


def derive_seed(base_seed: int, *parts: object) -> int:
    """A stable 32-bit seed for one request, independent of build order and of Python's hash salt."""
    key = ":".join(str(p) for p in (base_seed, *parts))
    return int.from_bytes(hashlib.sha256(key.encode()).digest()[:4], "big")


GENERATORS: Registry[Generator] = Registry("generator")
GENERATORS.register("rules", "talkdem.speech.rules_v3:RulesV3Generator")  # the default: rules-v3
GENERATORS.register("rules-v3", "talkdem.speech.rules_v3:RulesV3Generator")

CURRENT_GENERATOR = "rules"
"""The generator that builds the dataset by default (its phrase banks: `rules-v3`)."""

RETIRED = {"rules-v2": ("500d9bf", "builders/generation/rules.py")}
"""Retired generators -> (the commit where their code last lived, its path): git keeps it (`git show COMMIT:PATH`)."""


def register_generator(name: str, factory: str | Callable[[], Generator]) -> None:
    """Register a generator's factory, or its `module:attribute` (imported when the generator is asked for)."""
    GENERATORS.register(name, factory)


def check_generator_name(name: str) -> None:
    """Refuse a retired generator (naming the commit that has it) or an unknown one (listing the known)."""
    if name in RETIRED:
        commit, path = RETIRED[name]
        raise UnknownNameError(
            f"generator '{name}' is retired: its code last lived in commit {commit} "
            f"(git show {commit}:{path}); the current generator is '{CURRENT_GENERATOR}' "
            f"({GENERATORS.create(CURRENT_GENERATOR).prompt_version})"
        )
    GENERATORS.entry(name)


def get_generator(name: str) -> Generator:
    """A generator by registry name; a retired name names its last commit, unknown names list the known ones."""
    check_generator_name(name)
    return GENERATORS.create(name)
