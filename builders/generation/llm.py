"""The LLM generator: the paper's prompts, filled per request, sent to any text backend in one batch.

A backend is anything with `generate(prompts: list[str]) -> list[str]` (the planner issue's LLM backends
implement it). The prompts are versioned text files under `builders/prompts/<version>/`; the version
recorded with every row is the folder name plus a digest of the files, so edited prompts cannot pass for
the old ones.
"""

from __future__ import annotations

import hashlib
from collections.abc import Sequence
from functools import cached_property
from pathlib import Path
from typing import Protocol

from builders.generation.base import CLEAN, GenerationRequest
from builders.lexicon import display_name

__all__ = ["PROMPTS_DIR", "LLMGenerator", "TextBackend", "room_of", "scene_list"]

PROMPTS_DIR = Path(__file__).resolve().parent.parent / "prompts"
_ROOMS = {0: "kitchen", 2: "living room", 3: "bedroom", 4: "bathroom"}


class TextBackend(Protocol):
    """A text generator: one completion per prompt, in order."""

    def generate(self, prompts: list[str]) -> list[str]: ...


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
    """Prompted generation through a backend; output post-processing keeps the first non-empty line."""

    def __init__(self, backend: TextBackend, *, version: str = "v1", name: str = "llm") -> None:
        self.backend = backend
        self.version = version
        self.name = name
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

    def generate(self, requests: Sequence[GenerationRequest]) -> list[str]:
        prompts = [self.prompt(r) for r in requests]
        outputs = self.backend.generate(prompts)
        if len(outputs) != len(prompts):
            raise ValueError(f"backend returned {len(outputs)} completions for {len(prompts)} prompts")
        return [self._postprocess(o) for o in outputs]

    @staticmethod
    def _postprocess(output: str) -> str:
        lines = [line.strip() for line in output.strip().splitlines() if line.strip()]
        text = lines[0] if lines else ""
        return text.strip('"').strip()
