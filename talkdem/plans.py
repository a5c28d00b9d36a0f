"""What a plan is, checked in one place: a sequence of skill strings.

Every entry point that accepts plans from outside (a plan file for `talkdem score` or `talkdem simulate`, the
`evaluate` metric, a stored episode record) checks them here, so a malformed plan fails the same way
everywhere. A plain string is refused explicitly: it is a `Sequence[str]`, but it is one skill, not a plan,
and iterating it would turn "find an apple" into fourteen one-letter skills.
"""

from __future__ import annotations

from collections.abc import Sequence

__all__ = ["Plan", "PlanFormatError", "as_plan", "check_plan"]

Plan = tuple[str, ...]

_EXAMPLE = '["find an apple", "pick up the apple", "done"]'


class PlanFormatError(ValueError):
    """A value that is not a plan (a list of skill strings)."""


def as_plan(value: object) -> Plan | None:
    """The plan as a tuple, or None when `value` is not a sequence of strings."""
    if isinstance(value, str | bytes) or not isinstance(value, Sequence):
        return None
    if not all(isinstance(step, str) for step in value):
        return None
    return tuple(value)


def check_plan(value: object, where: str) -> Plan:
    """The plan as a tuple; a `PlanFormatError` naming `where` (file and line, or id) otherwise."""
    plan = as_plan(value)
    if plan is None:
        got = "a string" if isinstance(value, str) else type(value).__name__
        raise PlanFormatError(f"{where}: a plan must be a list of skill strings (e.g. {_EXAMPLE}), got {got}")
    return plan
