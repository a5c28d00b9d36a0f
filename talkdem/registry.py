"""One small registry for everything chosen by name: LLM backends, mitigation strategies, dataset generators.

An entry names its implementation as `module:attribute` (imported only when the entry is loaded, so
`talkdem --help` never imports a backend) or gives a factory directly, plus a display label. Unknown names
are refused with the known ones and a did-you-mean; the CLI's choices and the reports' labels are read from
the same entries, so a new strategy or backend is registered in one place.
"""

from __future__ import annotations

import difflib
import importlib
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Generic, TypeVar

__all__ = ["Registry", "RegistryEntry", "UnknownNameError"]

T = TypeVar("T")


class UnknownNameError(ValueError):
    """A name that no entry of the registry has."""


@dataclass(frozen=True)
class RegistryEntry(Generic[T]):
    name: str
    target: str | Callable[..., T]
    """`module:attribute` (imported on load) or the factory itself."""
    label: str
    """How reports and pages show the entry."""


class Registry(Generic[T]):
    """Named factories of `T`, in registration order."""

    def __init__(self, kind: str) -> None:
        self.kind = kind
        self._entries: dict[str, RegistryEntry[T]] = {}

    def register(self, name: str, target: str | Callable[..., T], label: str | None = None) -> None:
        self._entries[name] = RegistryEntry(name, target, label or name)

    def __contains__(self, name: object) -> bool:
        return name in self._entries

    def __iter__(self) -> Iterator[str]:
        return iter(self._entries)

    def __len__(self) -> int:
        return len(self._entries)

    def names(self) -> tuple[str, ...]:
        return tuple(self._entries)

    def labels(self) -> dict[str, str]:
        """name -> label, in registration order."""
        return {name: entry.label for name, entry in self._entries.items()}

    def entry(self, name: str) -> RegistryEntry[T]:
        if name not in self._entries:
            close = difflib.get_close_matches(name, self._entries, n=1)
            hint = f"; did you mean '{close[0]}'?" if close else ""
            raise UnknownNameError(f"unknown {self.kind} '{name}' (known: {', '.join(self._entries)}){hint}")
        return self._entries[name]

    def factory(self, name: str) -> Callable[..., T]:
        """The class or function behind `name`, imported now if it was registered as `module:attribute`."""
        target = self.entry(name).target
        if callable(target):
            return target
        module_name, attribute = target.split(":")
        loaded: Callable[..., T] = getattr(importlib.import_module(module_name), attribute)
        return loaded

    def create(self, name: str, *args: object, **kwargs: object) -> T:
        return self.factory(name)(*args, **kwargs)
