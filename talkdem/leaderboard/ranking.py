"""Which runs may be ranked against each other, and their ranks.

Runs are ranked only within a comparable group: the same dataset (hash) and the same episodes (task x
condition set, `coverage.task_set`). Reference-plan (oracle) records are never ranked. The rank key is the
average success rate over the 15 pattern x level conditions; equal keys share a rank (1, 2, 2, 4), and
within a tie rows are listed by average retention, clean success rate, then name.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

__all__ = ["RANK_KEY", "ComparableGroup", "Standings", "rank_records"]

RANK_KEY = "average success rate over the 15 pattern × level conditions (higher is better)"
_TIE_DIGITS = 4  # records round rates to 1e-4: equal at that precision is a tie


@dataclass(frozen=True)
class ComparableGroup:
    """Records over the same episodes of the same dataset, ranked."""

    dataset_hash: str
    task_set: str
    coverage: dict[str, Any]
    ranked: tuple[tuple[int, dict[str, Any]], ...]
    """(rank, record), best first; tied records share a rank."""


@dataclass(frozen=True)
class Standings:
    groups: tuple[ComparableGroup, ...]
    """Largest coverage first (then most runs)."""
    reference: tuple[dict[str, Any], ...]
    """Reference-plan records, shown apart and never ranked."""


def _main(record: dict[str, Any], name: str) -> float:
    value = record["results"]["talkdem"].get(name)
    return -1.0 if value is None else round(float(value), _TIE_DIGITS)


def rank_records(records: Sequence[dict[str, Any]]) -> Standings:
    """Split records into comparable groups and rank each (standard competition ranking)."""
    grouped: dict[tuple[str, str], list[dict[str, Any]]] = {}
    reference = []
    for record in records:
        if record.get("reference"):
            reference.append(record)
            continue
        key = (record["config"]["dataset_hash"], record["coverage"]["task_set"])
        grouped.setdefault(key, []).append(record)
    groups = []
    for (dataset, task_set), members in grouped.items():
        members.sort(
            key=lambda r: (
                -_main(r, "average_sr"),
                -_main(r, "average_retention"),
                -_main(r, "clean_sr"),
                r["config"]["run_name"],  # a stable order within a tie, whatever order the files came in
                r["run_id"],
            )
        )
        ranked: list[tuple[int, dict[str, Any]]] = []
        for position, record in enumerate(members, start=1):
            tied = ranked and _main(ranked[-1][1], "average_sr") == _main(record, "average_sr")
            ranked.append((ranked[-1][0] if tied else position, record))
        groups.append(ComparableGroup(dataset, task_set, members[0]["coverage"], tuple(ranked)))
    groups.sort(
        key=lambda g: (
            -sum(g.coverage["tasks_per_condition"].values()),
            -len(g.ranked),
            g.dataset_hash,
            g.task_set,
        )
    )
    return Standings(tuple(groups), tuple(reference))
