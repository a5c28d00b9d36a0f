"""The client-side tokenizer of a served model: the split into context and continuation tokens must be the one
the in-process backends make, so a served run scores exactly the tokens a local run scores.

Two sources, both local (nothing is downloaded):
- a GGUF file or a catalog model name (`talkdem models`): the file's own vocabulary through llama.cpp with
  `vocab_only` (no weights are loaded), split by `GGUFTokenSplit` as `talkdem.llm.backends.llamacpp` splits;
- a folder with a Hugging Face tokenizer (`tokenizer.json`, ...): split by `HFTokenSplit` as `talkdem.llm.backends.hf`
  splits.

The BOS rule is the model's own (GGUF metadata `tokenizer.ggml.add_bos_token`; the HF tokenizer's
`add_bos_token`); `add_bos` overrides it for a server started with another rule.
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import os
from pathlib import Path
from typing import Any, Protocol

from talkdem.llm.backends.tokenizing import GGUFTokenSplit, HFTokenSplit

__all__ = ["ServedTokenizer", "load_tokenizer"]


class ServedTokenizer(Protocol):
    name: str
    """What the run header records: the catalog name, the file or folder name (no machine path)."""
    revision: str
    """A content hash of the vocabulary source (the GGUF's SHA-256, or the tokenizer files' hash)."""
    bos_id: int | None
    """The BOS token the context starts with, or None when the model takes none."""

    def encode(self, text: str) -> list[int]:
        """Tokens of `text` without special tokens (a continuation)."""

    def context_ids(self, context: str) -> list[int]:
        """Tokens of a context, with BOS when the model's rule asks for it."""

    def piece(self, token: int) -> bytes:
        """The bytes of one token (for checking what a server echoes)."""


class _GGUFTokenizer(GGUFTokenSplit):
    def __init__(self, path: Path, name: str, revision: str, add_bos: bool | None) -> None:
        os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")
        from llama_cpp import Llama

        try:  # llama.cpp prints a context warning for a vocabulary-only model even when not verbose
            from llama_cpp._utils import suppress_stdout_stderr

            quiet: Any = suppress_stdout_stderr(disable=False)
        except ImportError:
            quiet = contextlib.nullcontext()
        with quiet:
            llm: Any = Llama(model_path=str(path), vocab_only=True, verbose=False)
        super().__init__(llm, add_bos)
        self.name, self.revision = name, revision


class _HFTokenizer(HFTokenSplit):
    def __init__(self, folder: Path, add_bos: bool | None) -> None:
        from transformers import AutoTokenizer

        super().__init__(AutoTokenizer.from_pretrained(str(folder), local_files_only=True), add_bos)
        self.name = folder.name
        digest = hashlib.sha256()
        for file in sorted(p for p in folder.iterdir() if p.is_file() and "token" in p.name):
            digest.update(file.name.encode() + b"\0" + file.read_bytes())
        self.revision = digest.hexdigest()


@functools.lru_cache(maxsize=8)
def load_tokenizer(source: str, add_bos: bool | None = None) -> ServedTokenizer:
    """A GGUF file, a catalog model name, or a local folder holding a Hugging Face tokenizer (loaded once per
    process: the clients of a concurrent run share it)."""
    from talkdem.llm.interface.base import file_sha256
    from talkdem.llm.interface.models import get_model, model_path

    spec = get_model(source)
    if spec is not None:
        return _GGUFTokenizer(model_path(spec.name), spec.name, spec.sha256, add_bos)
    path = Path(source).expanduser()
    if path.is_dir():
        return _HFTokenizer(path, add_bos)
    if path.is_file():
        return _GGUFTokenizer(path, path.name, file_sha256(path), add_bos)
    raise FileNotFoundError(
        f"{source}: a tokenizer must be a model name (`talkdem models`), a GGUF file, or a local folder "
        "with a Hugging Face tokenizer (the served model's own tokenizer)"
    )
