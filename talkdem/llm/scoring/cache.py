"""A result cache that wraps any backend: answers already computed are read from SQLite, not the model.

Every entry is keyed by the sha256 of (model identity key, method, request fields), so a different model,
weights file (its content hash is in the identity) or served endpoint never reads another's results.
Only the misses of a batch go to the model, in one call, in their original order.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import sqlite3
import threading
from collections.abc import Callable, Iterator, Sequence
from contextlib import closing
from pathlib import Path
from typing import Any, TypeVar

from talkdem.llm.interface.base import BestContinuation, LanguageModel
from talkdem.llm.interface.requests import GenerateRequest, LoglikelihoodRequest

__all__ = ["CacheFileError", "CachedLM", "cache_key", "open_cache"]

_T = TypeVar("_T")
_LOOKUP_CHUNK = 500  # well under SQLite's limit on bound parameters


def cache_key(identity_key: str, method: str, fields: Sequence[Any]) -> str:
    """sha256 of the JSON of (model identity, method, request fields)."""
    blob = json.dumps([identity_key, method, list(fields)], ensure_ascii=False, separators=(",", ":"))
    return hashlib.sha256(blob.encode()).hexdigest()


class CacheFileError(ValueError):
    """The `--cache` file cannot serve as a result cache: a folder, not SQLite, or corrupted."""


def _unusable(path: Path, exc: BaseException) -> CacheFileError:
    return CacheFileError(
        f"{path}: not a usable SQLite result cache ({type(exc).__name__}: {exc}); give --cache a new file name "
        "(a cache only saves time: a fresh one recomputes what it held)"
    )


def open_cache(path: Path) -> sqlite3.Connection:
    """The cache database at `path` (created if missing), checked: a folder, a file that is not SQLite or a
    damaged one is a `CacheFileError` naming the file, before any model work (not mid-run)."""
    if path.is_dir():
        raise CacheFileError(f"{path}: is a folder; --cache takes a file (e.g. {path / 'cache.sqlite'})")
    path.parent.mkdir(parents=True, exist_ok=True)
    try:
        db = sqlite3.connect(str(path), check_same_thread=False)
        db.execute("PRAGMA journal_mode=WAL")
        db.execute("CREATE TABLE IF NOT EXISTS results (key TEXT PRIMARY KEY, value TEXT NOT NULL)")
        db.commit()
        # A file that is SQLite only in its header, or damaged further in, fails here.
        with closing(db.execute("PRAGMA quick_check")) as cursor:
            verdict = [str(row[0]) for row in cursor]
    except sqlite3.Error as exc:
        raise _unusable(path, exc) from None
    if verdict != ["ok"]:
        db.close()
        raise _unusable(path, sqlite3.DatabaseError("; ".join(verdict)[:200]))
    return db


class CachedLM(LanguageModel):
    """`inner` behind a SQLite cache at `path`; `hits` and `misses` count answered requests.

    Every call of the interface goes through the cache: `score_continuations` and `best_continuation` are
    keyed by context and candidates and answered by `inner`'s own (fast) path on a miss, so the planner takes
    the same path through the cache as without it.
    """

    def __init__(self, inner: LanguageModel, path: str | Path) -> None:
        self.inner = inner
        self.identity = inner.identity
        self.supports_loglikelihood = inner.supports_loglikelihood
        self.supports_json_schema = inner.supports_json_schema
        self.path = Path(path)
        self.hits = 0
        self.misses = 0
        self._lock = threading.Lock()
        self._db = open_cache(self.path)

    # -- the interface --------------------------------------------------------------------------------
    def loglikelihood(self, requests: Sequence[LoglikelihoodRequest]) -> list[float]:
        return self._through_cache(
            "loglikelihood",
            [(r.context, r.continuation) for r in requests],
            lambda indices: self.inner.loglikelihood([requests[i] for i in indices]),
        )

    def generate(self, requests: Sequence[GenerateRequest]) -> list[str]:
        return self._through_cache(
            "generate",
            # `chat`, `system` and `json_schema` join the key only when set, so entries cached before the fields
            # existed keep their keys.
            [
                (
                    r.prompt,
                    r.max_new_tokens,
                    list(r.stop),
                    r.temperature,
                    r.seed,
                    *(() if r.chat else ("raw",)),
                    *((("system", r.system),) if r.system else ()),
                    *((("json_schema", r.json_schema),) if r.json_schema else ()),
                )
                for r in requests
            ],
            lambda indices: self.inner.generate([requests[i] for i in indices]),
        )

    def score_continuations(self, context: str, continuations: Sequence[str]) -> list[float]:
        return self._through_cache(
            "score_continuations",
            [(context, c) for c in continuations],
            lambda indices: list(self.inner.score_continuations(context, [continuations[i] for i in indices])),
        )

    def best_continuation(self, context: str, continuations: Sequence[str]) -> BestContinuation:
        # One entry per (context, candidate list): the answer depends on all candidates together.
        (found,) = self._through_cache(
            "best_continuation",
            [(context, list(continuations))],
            lambda _: [dataclasses.asdict(self.inner.best_continuation(context, continuations))],
        )
        return BestContinuation(**found)

    def token_count(self, text: str) -> int:
        return self.inner.token_count(text)

    def run_info(self) -> dict[str, str]:
        return self.inner.run_info()

    def runtime(self) -> dict[str, str]:
        return self.inner.runtime()

    def close(self) -> None:
        with self._lock:
            self._db.close()

    def __enter__(self) -> CachedLM:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def __len__(self) -> int:
        with self._lock, closing(self._db.execute("SELECT COUNT(*) FROM results")) as cursor:
            count: int = cursor.fetchone()[0]
        return count

    # -- the cache ------------------------------------------------------------------------------------
    def _through_cache(
        self,
        method: str,
        fields: Sequence[Sequence[Any]],
        compute: Callable[[list[int]], list[_T]],
    ) -> list[_T]:
        keys = [cache_key(self.identity.key(), method, f) for f in fields]
        found = self._lookup(keys)
        missing = [i for i, key in enumerate(keys) if key not in found]
        results: list[Any] = [found.get(key) for key in keys]
        if missing:
            # Identical requests in one batch go to the model once.
            unique = list(dict.fromkeys(keys[i] for i in missing))
            first_index: dict[str, int] = {}
            for i in missing:
                first_index.setdefault(keys[i], i)
            computed = compute([first_index[key] for key in unique])
            if len(computed) != len(unique):
                raise RuntimeError(
                    f"{self.identity.key()}: {method} returned {len(computed)} results for {len(unique)} requests"
                )
            fresh = dict(zip(unique, computed, strict=True))
            self._store(fresh)
            for i in missing:
                results[i] = fresh[keys[i]]
        with self._lock:
            self.hits += len(keys) - len(missing)
            self.misses += len(missing)
        return results

    def _lookup(self, keys: Sequence[str]) -> dict[str, Any]:
        found: dict[str, Any] = {}
        unique = list(dict.fromkeys(keys))
        with self._lock:
            try:
                for chunk in _chunks(unique, _LOOKUP_CHUNK):
                    placeholders = ",".join("?" * len(chunk))
                    query = f"SELECT key, value FROM results WHERE key IN ({placeholders})"
                    with closing(self._db.execute(query, chunk)) as cursor:
                        found.update((key, json.loads(value)) for key, value in cursor)
            except (sqlite3.Error, json.JSONDecodeError) as exc:
                raise _unusable(self.path, exc) from None
        return found

    def _store(self, entries: dict[str, Any]) -> None:
        with self._lock:
            try:
                self._db.executemany(
                    "INSERT OR REPLACE INTO results (key, value) VALUES (?, ?)",
                    [(key, json.dumps(value)) for key, value in entries.items()],
                )
                self._db.commit()
            except sqlite3.Error as exc:
                raise _unusable(self.path, exc) from None


def _chunks(items: Sequence[str], size: int) -> Iterator[list[str]]:
    for start in range(0, len(items), size):
        yield list(items[start : start + size])
