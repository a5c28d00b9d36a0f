"""The split of a scoring request into tokens, written once for every backend that tokenizes on this side.

SayCan's protocol tokenizes the context and the continuation separately and concatenates them; a context starts
with the BOS token when the rule says so. The rule is the model's own (a Hugging Face tokenizer's
`add_bos_token`; a GGUF's `tokenizer.ggml.add_bos_token`, as llama.cpp applies it), or an override for a server
started with another rule (`add_bos`). Two vocabularies implement it:

- `HFTokenSplit`: a transformers tokenizer (the hf and vllm backends, a served model's tokenizer folder);
- `GGUFTokenSplit`: a GGUF vocabulary through llama.cpp (the llamacpp backend, a served model's GGUF file).

A served run scores exactly the tokens a local run scores because both go through the same class.
"""

from __future__ import annotations

import threading
from abc import ABC, abstractmethod
from typing import Any

__all__ = ["GGUFTokenSplit", "HFTokenSplit", "TokenSplit", "bos_to_use"]


def bos_to_use(bos: int | None, own_rule: bool, add_bos: bool | None) -> int | None:
    """The BOS token a context starts with: the vocabulary's `bos` when the rule (the model's own unless `add_bos`
    overrides it) asks for one and the vocabulary has one; None otherwise."""
    use = own_rule if add_bos is None else add_bos
    return int(bos) if use and bos is not None else None


class TokenSplit(ABC):
    """Contexts and continuations as token ids, by one vocabulary and one BOS rule."""

    bos_id: int | None
    """The BOS token every context starts with, or None when the rule adds none."""

    @abstractmethod
    def encode(self, text: str) -> list[int]:
        """Tokens of `text` without special tokens (a continuation, or a context before its BOS)."""

    @abstractmethod
    def piece(self, token: int) -> bytes:
        """The bytes of one token (for checking what a server echoes)."""

    def context_ids(self, context: str) -> list[int]:
        """Tokens of a context: BOS first when the rule asks for it."""
        ids = self.encode(context)
        return [self.bos_id, *ids] if self.bos_id is not None else ids


class HFTokenSplit(TokenSplit):
    """A transformers tokenizer (or one with its interface, such as vLLM's)."""

    def __init__(self, tokenizer: Any, add_bos: bool | None = None) -> None:
        self.tokenizer = tokenizer
        bos = getattr(tokenizer, "bos_token_id", None)
        # Models trained with a BOS token expect it; SmolLM2 has none in its metadata by default.
        own_rule = bos is not None and bool(getattr(tokenizer, "add_bos_token", False))
        self.bos_id = bos_to_use(bos, own_rule, add_bos)

    def encode(self, text: str) -> list[int]:
        ids: list[int] = self.tokenizer(text, add_special_tokens=False).input_ids
        return ids

    def piece(self, token: int) -> bytes:
        return str(self.tokenizer.decode([token])).encode()


class GGUFTokenSplit(TokenSplit):
    """A GGUF vocabulary through a `llama_cpp.Llama` (a loaded model, or one opened with `vocab_only`)."""

    def __init__(self, llm: Any, add_bos: bool | None = None) -> None:
        self._llm = llm
        self._lock = threading.Lock()  # one vocabulary may serve every client thread of a concurrent run
        # The model's own rule as llama.cpp applies it: does tokenizing with specials start with BOS?
        bos = int(llm.token_bos())
        own_rule = llm.tokenize(b"a", add_bos=True, special=False)[:1] == [bos]
        self.bos_id = bos_to_use(bos, own_rule, add_bos)

    def encode(self, text: str) -> list[int]:
        with self._lock:
            ids: list[int] = self._llm.tokenize(text.encode(), add_bos=False, special=False)
        return ids

    def piece(self, token: int) -> bytes:
        with self._lock:
            return bytes(self._llm.detokenize([token]))
