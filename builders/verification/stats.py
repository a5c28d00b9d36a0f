"""How many attempts a variant may take to pass verification, and the paper's attempt statistics over built rows.

Shared by the build (`builders.build`), which regenerates up to `MAX_ATTEMPTS`, and the card's LLM statistics
(`builders.reporting.llm_stats`), which report them; a module of its own so that neither imports the other.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterable
from typing import Any

from talkdem.schema import CLEAN

__all__ = ["MAX_ATTEMPTS", "verification_stats"]

MAX_ATTEMPTS = 3
"""First attempt plus up to two regenerations."""


def verification_stats(rows: Iterable[dict[str, Any]]) -> dict[str, Any]:
    """The paper's attempt statistics over pattern variants (clean controls reported apart)."""
    variants = [r for r in rows if r["pattern"] != CLEAN]
    attempts = Counter(r["verification"]["attempts"] for r in variants)
    passed = Counter(r["verification"]["attempts"] for r in variants if r["verification"]["passed"])
    failed = [r for r in variants if not r["verification"]["passed"]]
    failed_checks = Counter(c for r in failed for c in r["verification"]["failed_checks"])
    total = len(variants)
    verified = sum(passed.values())
    return {
        "variants": total,
        "first_attempt_passed": passed[1],
        "regenerated": total - attempts[1],
        "second_attempt_passed": passed[2],
        "third_attempt": attempts[3],
        "third_attempt_passed": passed[3],
        "verified": verified,
        "verified_share": round(verified / total, 4) if total else 0.0,
        "kept_with_failed_checks": len(failed),
        "failed_checks": dict(sorted(failed_checks.items())),
    }
