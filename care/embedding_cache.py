"""Sentence embeddings cached on disk by (text, encoder): each text is encoded once per encoder, ever.

The cache of one encoder is a folder of shards (`<digest>.npz`: the texts' SHA-256 keys and their vectors),
one shard per batch of new texts. A shard is written whole or not at all (`talkdem.files.replacing`), so a killed
run never leaves a torn file, and concurrent runs each add their own shard: nothing is ever rewritten in place.
This is the one cache of embeddings: CARE's queries and its memory bank (`care.memory`) both go through it.
"""

from __future__ import annotations

import hashlib
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from talkdem.files import replacing
from talkdem.paths import cache_dir

__all__ = ["CachedEncoder", "text_key"]


def text_key(text: str) -> str:
    return hashlib.sha256(text.encode()).hexdigest()


class CachedEncoder:
    """Wraps an encoder (texts -> unit-normalized float64 rows); returns exactly what it would return."""

    def __init__(
        self,
        encode: Callable[[Sequence[str]], NDArray[np.float64]],
        encoder_name: str,
        folder: Path | None = None,
    ) -> None:
        self._encode = encode
        self.encoder_name = encoder_name
        self.folder = (folder or cache_dir() / "embeddings") / hashlib.sha256(encoder_name.encode()).hexdigest()[:16]
        self._vectors: dict[str, NDArray[np.float64]] = {}
        self._loaded: set[str] = set()
        self.encoded = 0
        """Texts that went through the encoder (cache misses) in this process."""

    def _load_shards(self) -> None:
        if not self.folder.is_dir():
            return
        for shard in sorted(self.folder.glob("*.npz")):
            if shard.name in self._loaded:
                continue
            with np.load(shard) as data:
                for key, vector in zip(data["keys"].tolist(), data["vectors"], strict=True):
                    self._vectors.setdefault(str(key), vector)
            self._loaded.add(shard.name)

    def _save_shard(self, keys: list[str], vectors: NDArray[np.float64]) -> None:
        self.folder.mkdir(parents=True, exist_ok=True)
        name = hashlib.sha256("".join(keys).encode()).hexdigest()[:24] + ".npz"
        with replacing(self.folder / name) as scratch, scratch.open("wb") as handle:
            np.savez(handle, keys=np.array(keys), vectors=vectors)  # a handle: savez adds no `.npz` to it
        self._loaded.add(name)

    def uncached(self, texts: Sequence[str]) -> int:
        """How many distinct texts of `texts` a call would send to the encoder (the shards on disk counted)."""
        keys = {text_key(t) for t in texts}
        if any(k not in self._vectors for k in keys):
            self._load_shards()
        return sum(1 for k in keys if k not in self._vectors)

    def __call__(self, texts: Sequence[str]) -> NDArray[np.float64]:
        keys = [text_key(t) for t in texts]
        if any(k not in self._vectors for k in keys):
            self._load_shards()
        missing: dict[str, str] = {}
        for key, text in zip(keys, texts, strict=True):
            if key not in self._vectors:
                missing.setdefault(key, text)
        if missing:
            fresh = np.asarray(self._encode(list(missing.values())), dtype=np.float64)
            self.encoded += len(missing)
            new_keys = list(missing)
            for key, vector in zip(new_keys, fresh, strict=True):
                self._vectors[key] = vector
            self._save_shard(new_keys, fresh)
        if not keys:
            return np.zeros((0, 0))
        return np.stack([self._vectors[k] for k in keys])
