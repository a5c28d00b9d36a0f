"""The LLM generator: the paper's prompts, filled per request, sent to any text backend in one batch.

The backend is any `talkdem.llm` language model (`hf`, `llamacpp`, `vllm`, `openai`): anything with
`generate(requests: Sequence[GenerateRequest]) -> list[str]`. The prompts are versioned text files under
`builders/prompts/<version>/`; the version recorded with every row is the folder name plus a digest of the
files, so edited prompts cannot pass for the old ones.

Decoding: the first attempt is greedy. A regeneration (the build asks again for a variant that failed
verification) samples at `retry_temperature` with the request's seed: greedy decoding would only repeat the
failed text, and the seed keeps the rebuild reproducible on backends that honour it.
"""

from __future__ import annotations

import hashlib
from collections.abc import Sequence
from functools import cached_property
from pathlib import Path
from typing import Protocol

from builders.generation.base import CLEAN, GenerationRequest
from builders.lexicon import display_name
from talkdem.llm.requests import GenerateRequest

__all__ = ["PROMPTS_DIR", "LLMGenerator", "TextBackend", "room_of", "scene_list"]

PROMPTS_DIR = Path(__file__).resolve().parent.parent / "prompts"
_ROOMS = {0: "kitchen", 2: "living room", 3: "bedroom", 4: "bathroom"}


class TextBackend(Protocol):
    """A text generator: one completion per request, in order (every `talkdem.llm` backend is one)."""

    def generate(self, requests: Sequence[GenerateRequest]) -> list[str]: ...


def room_of(floor_plan: str) -> str:
    """AI2-THOR floor plans: 1-30 kitchens, 201-230 living rooms, 301-330 bedrooms, 401-430 bathrooms."""
    number = int(floor_plan.removeprefix("FloorPlan"))
    return _ROOMS.get(number // 100, "room")


def scene_list(floor_plan: str, scene_objects: Sequence[str]) -> str:
    """The paper's scene list: "A kitchen containing only the following items: apple, bowl, ..."."""
    names = sorted({display_name(t) for t in scene_objects})
    room = room_of(floor_plan)
    return f"A {room} containing only the following items:\n\n" + ", ".join(names)


class LLMGenerator:
    """Prompted generation through a backend; output post-processing keeps the first non-empty line.

    Args:
        backend: the language model.
        version: the prompt set (a folder under `builders/prompts/`).
        name: stored with every row as `generator`; by default `llm:<model name>` from the backend's identity.
        max_new_tokens: the longest utterance generated (the paper's utterances are 1-4 sentences).
        retry_temperature: sampling temperature of regenerations (attempt 2 and 3).
    """

    def __init__(
        self,
        backend: TextBackend,
        *,
        version: str = "v1",
        name: str | None = None,
        max_new_tokens: int = 160,
        retry_temperature: float = 0.7,
    ) -> None:
        self.backend = backend
        self.version = version
        identity = getattr(backend, "identity", None)
        self.name = name or (f"llm:{identity.name}" if identity is not None else "llm")
        self.max_new_tokens = max_new_tokens
        self.retry_temperature = retry_temperature
        self.folder = PROMPTS_DIR / version
        if not (self.folder / "clean.txt").is_file():
            raise FileNotFoundError(f"{self.folder}: no prompt set (expected clean.txt and <pattern>_<level>.txt)")

    @cached_property
    def prompt_version(self) -> str:
        digest = hashlib.sha256()
        for path in sorted(self.folder.glob("*.txt")):
            digest.update(path.name.encode() + b"\0" + path.read_bytes())
        return f"{self.version}+{digest.hexdigest()[:10]}"

    def template(self, pattern: str, level: int) -> str:
        name = "clean.txt" if pattern == CLEAN else f"{pattern}_{level}.txt"
        path = self.folder / name
        if not path.is_file():
            raise FileNotFoundError(f"{path}: no prompt for {pattern} level {level}")
        return path.read_text(encoding="utf-8")

    def prompt(self, request: GenerationRequest) -> str:
        task = request.task
        fields = {
            "clean": task.instruction if request.pattern == CLEAN else request.clean,
            "object": display_name(task.pddl_params.object_target),
            "scene": scene_list(task.floor_plan, task.scene.scene_objects),
        }
        text = self.template(request.pattern, request.level)
        for key, value in fields.items():
            text = text.replace("{" + key + "}", value)
        return text

    def request_for(self, request: GenerationRequest) -> GenerateRequest:
        """The backend request: greedy on the first attempt, seeded sampling on a regeneration."""
        temperature = 0.0 if request.attempt <= 1 else self.retry_temperature
        # No stop string: a chat model may open with a blank line; `_postprocess` keeps the first real one.
        return GenerateRequest(
            self.prompt(request),
            max_new_tokens=self.max_new_tokens,
            stop=(),
            temperature=temperature,
            seed=request.seed,
        )

    def generate(self, requests: Sequence[GenerationRequest]) -> list[str]:
        prompts = [self.request_for(r) for r in requests]
        outputs = self.backend.generate(prompts)
        if len(outputs) != len(prompts):
            raise ValueError(f"backend returned {len(outputs)} completions for {len(prompts)} prompts")
        return [self._postprocess(o) for o in outputs]

    @staticmethod
    def _postprocess(output: str) -> str:
        lines = [line.strip() for line in output.strip().splitlines() if line.strip()]
        text = lines[0] if lines else ""
        return text.strip('"').strip()
