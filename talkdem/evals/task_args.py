"""The inspect task's arguments (`-T conditions=... -T limit=... -T max_steps=...`), checked where they enter:
by the task when `inspect eval` builds it, and by `talkdem import-inspect` when it reads them back from a log
(where any JSON may stand). Both refuse a bad value with one line naming the argument and what it must be.

No inspect_ai import here: the importer's checks run before inspect is needed for anything else.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from talkdem.instructions import Instruction

__all__ = ["DEFAULT_CONDITIONS", "TaskArgs", "check_task_args"]

DEFAULT_CONDITIONS = "clean"
"""The task's `conditions` when none is given (the task function's default)."""


@dataclass(frozen=True)
class TaskArgs:
    conditions: str
    """Comma-separated, as `talkdem episodes --conditions` takes them."""
    limit: int | None
    max_steps: int

    def episodes(self) -> list[Instruction]:
        """The task's samples: exactly `talkdem episodes --conditions C --limit N`."""
        from talkdem.runs.sampling import select_episodes
        from talkdem.schema import parse_conditions

        return select_episodes(parse_conditions(self.conditions), self.limit)


def _count(value: object) -> int | None:
    """`value` when it is a whole number of at least 1 (true/false are no counts), else None."""
    return value if isinstance(value, int) and not isinstance(value, bool) and value >= 1 else None


def check_task_args(args: Mapping[str, object], where: str) -> TaskArgs:
    """`args` (missing ones take the task's defaults) as `TaskArgs`; a ValueError naming `where` and the
    argument otherwise. `conditions` may be a list: inspect splits `-T conditions=a,b` at the comma."""
    from talkdem.schema import parse_conditions
    from talkdem.sim.seam import DEFAULT_MAX_STEPS

    conditions = args.get("conditions", DEFAULT_CONDITIONS)
    if isinstance(conditions, list) and conditions and all(isinstance(c, str) for c in conditions):
        conditions = ",".join(conditions)
    if not isinstance(conditions, str):
        raise ValueError(
            f"{where}: task argument 'conditions' must be text such as 'clean,intrusion:3', got {conditions!r}"
        )
    try:
        parse_conditions(conditions)
    except ValueError as exc:
        raise ValueError(f"{where}: task argument 'conditions': {exc}") from None
    given_limit = args.get("limit")
    limit = _count(given_limit)
    if given_limit is not None and limit is None:
        raise ValueError(
            f"{where}: task argument 'limit' must be a whole number of tasks, at least 1 (or none), got {given_limit!r}"
        )
    given_steps = args.get("max_steps", DEFAULT_MAX_STEPS)
    max_steps = _count(given_steps)
    if max_steps is None:
        raise ValueError(f"{where}: task argument 'max_steps' must be a whole number, at least 1, got {given_steps!r}")
    return TaskArgs(conditions, limit, max_steps)
