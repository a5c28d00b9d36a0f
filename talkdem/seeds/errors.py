"""Errors raised when seed data is missing or malformed."""

from __future__ import annotations

from pathlib import Path

__all__ = ["SeedFormatError"]


class SeedFormatError(ValueError):
    """A seed or scene file is missing, unreadable, or lacks a field; the message names file and field."""

    def __init__(self, path: Path | str, field: str, problem: str) -> None:
        self.path = Path(path)
        self.field = field
        self.problem = problem
        where = f"{self.path}: field '{field}'" if field else str(self.path)
        super().__init__(f"{where}: {problem}")
