"""The LLM generator: the paper's prompts, filled per request, sent to any text backend in one batch.

The backend is any `talkdem.llm` language model (`hf`, `llamacpp`, `vllm`, `openai`): anything with
`generate(requests: Sequence[GenerateRequest]) -> list[str]`. The prompts are versioned text files under
`builders/prompts/<version>/`; the version recorded with every row is the folder name, a digest of the files
and of the output schema, and the output form (`+json` or `+text`), so edited prompts cannot pass for the old
ones and a row says whether its model answered in structured form.

Messages: each prompt is laid out as the paper's are, a "Role" paragraph and then the task, the inputs and the
output line. The role goes as the system message and the rest as the user message, so an instruct model sees
them through its own chat template (the backend applies it).

Structured output (the paper, appendix "Rule-Constrained Generation": "Both generation stages used structured
outputs"): on a backend that constrains decoding to a JSON schema (`supports_json_schema`: llama.cpp grammars,
vLLM guided decoding, an OpenAI-compatible server's `response_format`), the answer must be the object
`{"rewritten_instruction": "..."}` and is parsed strictly: anything else is `unparsable_output`. A backend
without it (transformers) gets the same prompt and its first non-empty line is taken (plain-text fallback).

Echoes: small instruct models often repeat their input or the prompt's own lines ("Return only the rewritten
instruction."). An output equal to the text it was asked to rewrite is `echo_of_input`; one that contains a
sentence or a section label of the prompt is `echo_of_prompt`. Both fail the utterance like a failed check.

Decoding: the first attempt is greedy. A regeneration (the build asks again for a variant that failed) samples
at `retry_temperature` with the request's seed: greedy decoding would only repeat the failed text, and the seed
keeps the rebuild reproducible on backends that honour it.
"""

from __future__ import annotations

import hashlib
import json
import re
import time
from collections.abc import Sequence
from functools import cached_property
from pathlib import Path
from typing import Any, Protocol

from talkdem.llm.interface.requests import GenerateRequest
from talkdem.speech.base import CLEAN, Generated, GenerationRequest
from talkdem.speech.lexicon import display_name

__all__ = [
    "ECHO_OF_INPUT",
    "ECHO_OF_PROMPT",
    "EMPTY_OUTPUT",
    "OUTPUT_FIELD",
    "OUTPUT_SCHEMA",
    "PROMPTS_DIR",
    "UNPARSABLE_OUTPUT",
    "LLMGenerator",
    "TextBackend",
    "echo_failures",
    "parse_structured",
    "parse_text",
    "room_of",
    "scene_list",
    "split_prompt",
]

PROMPTS_DIR = Path(__file__).resolve().parent.parent / "prompts"
_ROOMS = {0: "kitchen", 2: "living room", 3: "bedroom", 4: "bathroom"}

OUTPUT_FIELD = "rewritten_instruction"
"""The one field of the structured answer, named after the prompts' last line ("Return only the rewritten
instruction.")."""
OUTPUT_SCHEMA: dict[str, Any] = {
    "type": "object",
    "properties": {OUTPUT_FIELD: {"type": "string", "minLength": 1}},
    "required": [OUTPUT_FIELD],
    "additionalProperties": False,
}

UNPARSABLE_OUTPUT = "unparsable_output"
"""Structured mode: the answer is not exactly `{"rewritten_instruction": "<non-empty text>"}`."""
EMPTY_OUTPUT = "empty_output"
"""Plain-text mode: nothing but whitespace came back."""
ECHO_OF_INPUT = "echo_of_input"
"""The answer is the text it was asked to rewrite (the clean control, or the seed for a clean control)."""
ECHO_OF_PROMPT = "echo_of_prompt"
"""The answer contains a sentence or a section label of the prompt (e.g. "Return only the rewritten instruction")."""

_SENTENCE_END = re.compile(r"(?<=[.!?])\s+|\n+")
_MIN_ECHO_WORDS = 4  # shorter prompt fragments ("the target object") occur in honest answers


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


def split_prompt(text: str) -> tuple[str, str]:
    """(system, user): the paper's "Role:" paragraph as the system message, everything from "Task:" on (the
    instructions, inputs and output line) as the user message. A prompt without that layout is all user."""
    match = re.match(r"\s*Role:\s*\n(.*?)\n\s*(Task:\s*\n.*)\Z", text, flags=re.DOTALL)
    if match is None:
        return "", text.strip()
    return match.group(1).strip(), match.group(2).strip()


def _words(text: str) -> str:
    """Lowercase words joined by single spaces, padded: `" hi put the apple "` (for containment tests)."""
    return " " + " ".join(re.findall(r"[a-z0-9']+", text.lower())) + " "


def parse_structured(output: str) -> str | None:
    """The utterance of a structured answer, or None when the answer is not exactly one JSON object with the
    one string field (non-empty); whitespace inside the utterance, line breaks included, becomes one space."""
    try:
        answer = json.loads(output.strip())
    except (json.JSONDecodeError, RecursionError):
        return None
    if not isinstance(answer, dict) or set(answer) != {OUTPUT_FIELD} or not isinstance(answer[OUTPUT_FIELD], str):
        return None
    text = " ".join(answer[OUTPUT_FIELD].split())
    return text or None


def parse_text(output: str) -> str:
    """Plain-text fallback: the first non-empty line that is not a label ("Here is the rewritten instruction:"
    ends with a colon, which no utterance has), unquoted; empty when there is none."""
    lines = [line.strip() for line in output.strip().splitlines() if line.strip()]
    lines = [line for line in lines if not line.endswith(":")] or lines
    return lines[0].strip('"').strip() if lines else ""


def echo_failures(text: str, source: str, prompt: str) -> tuple[str, ...]:
    """`echo_of_input` when `text` is `source` (same words); `echo_of_prompt` when it holds a section label
    ("Target object:") or a sentence of at least four words from `prompt` outside `source`."""
    failures = []
    said = _words(text)
    if said.strip() and said == _words(source):
        failures.append(ECHO_OF_INPUT)
    rest = prompt.replace(source, "\n") if source else prompt
    labels = [line.strip() for line in rest.splitlines() if line.strip().endswith(":")]
    sentences = [s for s in _SENTENCE_END.split(rest) if len(_words(s).split()) >= _MIN_ECHO_WORDS]
    if any(label.lower() in text.lower() for label in labels) or any(_words(s) in said for s in sentences):
        failures.append(ECHO_OF_PROMPT)
    return tuple(failures)


class LLMGenerator:
    """Prompted generation through a backend, as system and user messages, in structured form where it can.

    Args:
        backend: the language model.
        version: the prompt set (a folder under `builders/prompts/`).
        name: stored with every row as `generator`; by default `llm:<model name>` from the backend's identity.
        max_new_tokens: the longest answer generated (the paper's utterances are 1-4 sentences; the JSON
            wrapper takes about ten tokens more).
        retry_temperature: sampling temperature of regenerations (attempt 2 and 3).
        structured: ask for the JSON answer when the backend can constrain decoding to a schema; False: always
            plain text.
        system_message: send the prompt's "Role" paragraph as the system message; False: one user message.
    """

    def __init__(
        self,
        backend: TextBackend,
        *,
        version: str = "v1",
        name: str | None = None,
        max_new_tokens: int = 200,
        retry_temperature: float = 0.7,
        structured: bool = True,
        system_message: bool = True,
    ) -> None:
        self.backend = backend
        self.version = version
        identity = getattr(backend, "identity", None)
        self.name = name or (f"llm:{identity.name}" if identity is not None else "llm")
        self.max_new_tokens = max_new_tokens
        self.retry_temperature = retry_temperature
        self.structured = structured and bool(getattr(backend, "supports_json_schema", False))
        self.system_message = system_message
        self.folder = PROMPTS_DIR / version
        if not (self.folder / "clean.txt").is_file():
            raise FileNotFoundError(f"{self.folder}: no prompt set (expected clean.txt and <pattern>_<level>.txt)")
        self._usage = {"generations": 0.0, "seconds": 0.0, "prompt_tokens": 0.0, "completion_tokens": 0.0}

    @property
    def output_form(self) -> str:
        """`json` (structured answers, parsed strictly) or `text` (the plain-text fallback)."""
        return "json" if self.structured else "text"

    @cached_property
    def prompt_version(self) -> str:
        digest = hashlib.sha256()
        for path in sorted(self.folder.glob("*.txt")):
            digest.update(path.name.encode() + b"\0" + path.read_bytes())
        if self.structured:
            digest.update(b"schema\0" + json.dumps(OUTPUT_SCHEMA, sort_keys=True).encode())
        if self.system_message:
            digest.update(b"system-message")
        return f"{self.version}+{digest.hexdigest()[:10]}+{self.output_form}"

    def template(self, pattern: str, level: int) -> str:
        name = "clean.txt" if pattern == CLEAN else f"{pattern}_{level}.txt"
        path = self.folder / name
        if not path.is_file():
            raise FileNotFoundError(f"{path}: no prompt for {pattern} level {level}")
        return path.read_text(encoding="utf-8")

    @staticmethod
    def source(request: GenerationRequest) -> str:
        """The text the request rewrites: the seed for a clean control, else the clean control."""
        return request.task.instruction if request.pattern == CLEAN else request.clean

    def prompt(self, request: GenerationRequest) -> str:
        task = request.task
        fields = {
            "clean": self.source(request),
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
        system, user = split_prompt(self.prompt(request)) if self.system_message else ("", self.prompt(request))
        # No stop string: a chat model may open with a blank line; `parse_text` keeps the first real one.
        return GenerateRequest(
            user,
            max_new_tokens=self.max_new_tokens,
            stop=(),
            temperature=temperature,
            seed=request.seed,
            system=system,
            json_schema=json.dumps(OUTPUT_SCHEMA, sort_keys=True) if self.structured else "",
        )

    def generate_checked(self, requests: Sequence[GenerationRequest]) -> list[Generated]:
        """One utterance per request, with its own failures: unparsable or empty answers and echoes. An
        unparsable answer is kept as the raw output (stripped), so the failure can be read in the row."""
        prompts = [self.request_for(r) for r in requests]
        started = time.perf_counter()
        outputs = self.backend.generate(prompts)
        self._usage["seconds"] += time.perf_counter() - started
        if len(outputs) != len(prompts):
            raise ValueError(f"backend returned {len(outputs)} completions for {len(prompts)} prompts")
        self._count_tokens(prompts, outputs)
        results = []
        for request, prompt, output in zip(requests, prompts, outputs, strict=True):
            parsed = parse_structured(output) if self.structured else parse_text(output)
            if not parsed:
                reason = UNPARSABLE_OUTPUT if self.structured else EMPTY_OUTPUT
                results.append(Generated(" ".join(output.split()), (reason,), utterance=False))
                continue
            full_prompt = f"{prompt.system}\n\n{prompt.prompt}"
            results.append(Generated(parsed, echo_failures(parsed, self.source(request), full_prompt)))
        return results

    def generate(self, requests: Sequence[GenerationRequest]) -> list[str]:
        return [result.text for result in self.generate_checked(requests)]

    def usage(self) -> dict[str, float]:
        """Totals since creation: generations, seconds inside the backend, prompt and completion tokens
        (counted by the backend's tokenizer on the messages' text, without the chat template's own tokens;
        0 when the backend counts no tokens)."""
        return dict(self._usage)

    def _count_tokens(self, prompts: Sequence[GenerateRequest], outputs: Sequence[str]) -> None:
        self._usage["generations"] += len(prompts)
        count = getattr(self.backend, "token_count", None)
        if count is None:
            return
        self._usage["prompt_tokens"] += sum(count(p.system) + count(p.prompt) for p in prompts)
        self._usage["completion_tokens"] += sum(count(o) for o in outputs)
