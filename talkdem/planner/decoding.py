"""Decoding of the words a strategy asks the model for before planning (CoT's answer, TOCC's rewrite).

REI-Bench's rule (`task_planner.py`, its CoT and TOCC branches): greedy, stopped at the first ".", of which
the last line is kept. REI-Bench continues the prompt as plain text; the default model (an instruct model,
as are all the paper's) then starts a numbered plan or says nothing (docs/strategies.md), so the prompt goes
through the model's chat template (`chat=True`; `chat=False` is REI-Bench's plain completion). The stop
rule also ends at "?" and "!", the other sentence ends (the benchmark's requests are often questions). On
top of it, so that nothing reaches the planner cut mid-sentence or looping without it being recorded:

- a token budget measured on the benchmark's longest instructions (docs/strategies.md): a sentence that
  restates even the longest instruction in full fits, so the cap is only reached by output that never ends;
- a repeated phrase (the same 1-8 words three times in a row) is cut after its first occurrence;
- every output gets a status, recorded in the episode's notes: `ok`, `loop_cut`, `truncated` (the budget
  ran out before a sentence end), or `empty` (nothing usable: no letter at all, e.g. a bare list number
  "1" cut at its "."). Nothing falls back silently to the original.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal

from talkdem.llm.interface.base import LanguageModel
from talkdem.llm.interface.requests import GenerateRequest

__all__ = ["MAX_NEW_TOKENS", "Generated", "GenerationStatus", "StepDecoding", "clean_generation", "cut_loop"]

GenerationStatus = Literal["ok", "loop_cut", "truncated", "empty"]

MAX_NEW_TOKENS = 128
"""The longest benchmark instruction is 89 tokens with the default model's tokenizer (docs/strategies.md):
a sentence restating even that one in full fits, with room for a leading line the last-line rule drops."""

_LOOP_WORDS = 8
_LOOP_REPEATS = 3
_WORD = re.compile(r"\S+")


def _norm(word: str) -> str:
    return word.strip(".,;:!?\"'()").lower()


def cut_loop(text: str) -> tuple[str, bool]:
    """`text` cut after the first occurrence of a phrase that then repeats (3 times in a row in all), and
    whether it was cut. The earliest repetition wins, then the shortest phrase: deterministic."""
    spans = [(m.start(), m.end()) for m in _WORD.finditer(text)]
    words = [_norm(text[a:b]) for a, b in spans]
    for start in range(len(words)):
        for size in range(1, _LOOP_WORDS + 1):
            end = start + size * _LOOP_REPEATS
            if end > len(words):
                break
            phrase = words[start : start + size]
            if any(phrase) and all(
                words[start + k * size : start + (k + 1) * size] == phrase for k in range(1, _LOOP_REPEATS)
            ):
                return text[: spans[start + size - 1][1]].rstrip(" ,;:"), True
    return text, False


@dataclass(frozen=True)
class Generated:
    text: str
    status: GenerationStatus


def clean_generation(raw: str, hit_cap: bool) -> Generated:
    """REI-Bench's last line of a completion cut at ".", loop-cut, with its status; a complete sentence gets
    its "." back (the stop string is not returned)."""
    lines = [line.strip() for line in raw.splitlines() if line.strip()]
    text = " ".join(lines[-1].split()) if lines else ""
    text, looped = cut_loop(text)
    if not any(ch.isalpha() for ch in text):
        return Generated("", "empty")
    if looped:
        return Generated(text, "loop_cut")
    if hit_cap:
        return Generated(text, "truncated")
    if text[-1] not in ".!?":
        text += "."
    return Generated(text, "ok")


@dataclass(frozen=True)
class StepDecoding:
    """How a strategy's generation step decodes (recorded in the run header as strategy options)."""

    max_new_tokens: int = MAX_NEW_TOKENS
    stop: tuple[str, ...] = (".", "?", "!")
    chat: bool = True
    """True: wrap the prompt in the model's chat template; False (REI-Bench): continue it as plain text."""

    def __post_init__(self) -> None:
        if self.max_new_tokens < 1:
            raise ValueError(f"max_new_tokens must be >= 1, got {self.max_new_tokens}")

    def run(self, model: LanguageModel, prompts: Sequence[str]) -> list[Generated]:
        requests = [
            GenerateRequest(p, max_new_tokens=self.max_new_tokens, stop=self.stop, chat=self.chat) for p in prompts
        ]
        outputs = model.generate(requests)
        # The backends return text without the stop string: a completion that used (nearly) the whole budget
        # did not stop by itself. Two tokens of slack for the stripped whitespace around it.
        return [clean_generation(raw, model.token_count(raw) >= self.max_new_tokens - 2) for raw in outputs]

    def options(self) -> dict[str, object]:
        return {"max_new_tokens": self.max_new_tokens, "stop": list(self.stop), "chat": self.chat}
