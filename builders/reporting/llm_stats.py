"""What an LLM build gives and costs: attempt statistics as the paper reports them, failure reasons, timing,
and the card's markdown fragment.

The paper (appendix "Rule-Constrained Generation") counts pattern variants that passed on the first attempt,
on the second, on the third, and those kept failing. The rows keep only each utterance's last attempt, so the
reasons of attempts that were regenerated come from the build's generation log (one record per attempt,
`builders.build.build_unit_logged`); costs come from the generator's usage (seconds inside the backend,
generations, tokens).
"""

from __future__ import annotations

import html
import json
from collections import Counter
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

from builders.generation.llm import ECHO_OF_INPUT, ECHO_OF_PROMPT, EMPTY_OUTPUT, UNPARSABLE_OUTPUT
from builders.verification.stats import MAX_ATTEMPTS, verification_stats
from talkdem.schema import CLEAN, PATTERN_CONFIGS

__all__ = ["SAMPLE_SUMMARY", "card_section", "generation_stats", "reason_group", "sample_card_section"]

SAMPLE_SUMMARY = Path("data") / "llm_sample" / "summary.json"
"""The committed LLM sample's summary, relative to the repository root (written by `builders.reporting.llm_sample`)."""

_OWN_REASONS = {
    UNPARSABLE_OUTPUT: "unparsable",
    EMPTY_OUTPUT: "unparsable",
    ECHO_OF_INPUT: "echo",
    ECHO_OF_PROMPT: "echo",
}


def reason_group(check: str) -> str:
    """`unparsable`, `echo` or `verifier` (a check of `builders.verification`)."""
    return _OWN_REASONS.get(check, "verifier")


def _attempt_table(records: Sequence[Mapping[str, Any]]) -> dict[str, dict[str, Any]]:
    table: dict[str, dict[str, Any]] = {}
    for attempt in range(1, MAX_ATTEMPTS + 1):
        these = [r for r in records if r["attempt"] == attempt]
        failed = [r for r in these if not r["passed"]]
        # Each failed utterance counts once per group: the first reason it failed for, in the order
        # unparsable, echo, verifier (an echo fails most verifier checks too; the echo is what went wrong).
        groups = Counter(
            min((reason_group(c) for c in r["failed_checks"]), key=["unparsable", "echo", "verifier"].index)
            for r in failed
            if r["failed_checks"]
        )
        table[str(attempt)] = {
            "generated": len(these),
            "passed": len(these) - len(failed),
            "failed_by_group": dict(sorted(groups.items())),
            "failed_checks": dict(sorted(Counter(c for r in failed for c in r["failed_checks"]).items())),
        }
    return table


def generation_stats(rows: Sequence[Mapping[str, Any]], logs: Iterable[Mapping[str, Any]]) -> dict[str, Any]:
    """The statistics of an LLM build's benchmark units: `rows` (their 16 rows each), `logs` (their logs)."""
    logs = list(logs)
    records = [a for log in logs for a in log.get("attempts", [])]
    variant_records = [a for a in records if a["pattern"] != CLEAN]
    variants = [r for r in rows if r["pattern"] != CLEAN]
    by_pattern = {}
    for pattern in PATTERN_CONFIGS:
        these = [r for r in variants if r["pattern"] == pattern]
        if these:
            stats = verification_stats(dict(r) for r in these)
            by_pattern[pattern] = {
                key: stats[key]
                for key in ("variants", "first_attempt_passed", "second_attempt_passed", "third_attempt_passed")
            } | {"kept_failing": stats["kept_with_failed_checks"]}
    usage_keys = ("generations", "seconds", "prompt_tokens", "completion_tokens")
    usage = {key: round(sum(float(log.get("usage", {}).get(key, 0.0)) for log in logs), 3) for key in usage_keys}
    generations = usage["generations"] or 1.0
    utterances = len(rows) or 1
    usage |= {
        "utterances": len(rows),
        "seconds_per_generation": round(usage["seconds"] / generations, 2),
        "seconds_per_utterance": round(usage["seconds"] / utterances, 2),
        "prompt_tokens_per_generation": round(usage["prompt_tokens"] / generations, 1),
        "completion_tokens_per_generation": round(usage["completion_tokens"] / generations, 1),
    }
    versions = sorted({str(r["prompt_version"]) for r in rows})
    return {
        "generator": sorted({str(r["generator"]) for r in rows}),
        "prompt_version": versions,
        "output_form": sorted({v.rsplit("+", 1)[-1] for v in versions}),
        "tasks": len({r["task_id"] for r in rows}),
        "variants": verification_stats(dict(r) for r in rows),
        "clean": verification_stats([{**r, "pattern": "x"} for r in rows if r["pattern"] == CLEAN]),
        "attempts": _attempt_table(variant_records),
        "clean_attempts": _attempt_table([a for a in records if a["pattern"] == CLEAN]),
        "by_pattern": by_pattern,
        "usage": usage,
    }


# --- the card's fragment ------------------------------------------------------------------------------------------
def _cell(text: str) -> str:
    """Text safe inside a markdown table cell: HTML escaped, pipes escaped, on one line."""
    return html.escape(" ".join(text.split()), quote=False).replace("|", "\\|")


def _share(part: int, whole: int) -> str:
    return f"{part:,}/{whole:,} ({100 * part / whole:.0f}%)" if whole else "0/0"


def card_section(stats: Mapping[str, Any], context: str = "", examples: Sequence[Mapping[str, Any]] = ()) -> str:
    """Markdown: "What `talkdem build --generator llm` gives and costs", from `generation_stats` output.

    `context` is a sentence saying what was run (model, machine, sample); `examples` are rows to show
    (pattern, level, instruction, verification)."""
    v = stats["variants"]
    total = v["variants"]
    lines = [
        "### What `talkdem build --generator llm` gives and costs",
        "",
        *([context, ""] if context else []),
        f"Of {total:,} pattern variants, {_share(v['first_attempt_passed'], total)} passed every check on the first "
        f"attempt, {v['second_attempt_passed']:,} more on the second and {v['third_attempt_passed']:,} on the third; "
        f"{v['kept_with_failed_checks']:,} kept failing after {MAX_ATTEMPTS} attempts and were kept with their failed "
        "checks (the paper's LLM: 4,451 of 4,500 on the first attempt, 20 on the second, 18 on the third, 11 kept "
        f"failing). Clean controls: {_share(stats['clean']['first_attempt_passed'], stats['clean']['variants'])} on "
        f"the first attempt, {_share(stats['clean']['verified'], stats['clean']['variants'])} within three, "
        f"{stats['clean']['kept_with_failed_checks']:,} kept failing.",
        "",
        "| Attempt | Variants generated | Passed | Failed: unparsable | Failed: echo | Failed: verifier checks |",
        "| ---: | ---: | ---: | ---: | ---: | ---: |",
    ]
    for attempt, row in stats["attempts"].items():
        groups = row["failed_by_group"]
        lines.append(
            f"| {attempt} | {row['generated']:,} | {_share(row['passed'], row['generated'])} | "
            f"{groups.get('unparsable', 0):,} | {groups.get('echo', 0):,} | {groups.get('verifier', 0):,} |"
        )
    first = Counter(stats["attempts"]["1"]["failed_checks"]).most_common(6)
    if first:
        lines += [
            "",
            "Most frequent failure reasons on the first attempt: " + ", ".join(f"`{c}` ({n})" for c, n in first),
        ]
    lines += [
        "",
        "| Pattern | Variants | First attempt | Second | Third | Kept failing |",
        "| --- | ---: | ---: | ---: | ---: | ---: |",
    ]
    for pattern, row in stats["by_pattern"].items():
        lines.append(
            f"| {pattern} | {row['variants']} | {row['first_attempt_passed']} | {row['second_attempt_passed']} | "
            f"{row['third_attempt_passed']} | {row['kept_failing']} |"
        )
    u = stats["usage"]
    lines += [
        "",
        f"Cost: {u['generations']:,.0f} generations in {u['seconds'] / 60:,.1f} minutes of generation, "
        f"{u['seconds_per_generation']:.1f} s per generation and {u['seconds_per_utterance']:.1f} s per delivered "
        f"utterance (regenerations included); {u['prompt_tokens_per_generation']:,.0f} prompt tokens and "
        f"{u['completion_tokens_per_generation']:,.0f} completion tokens per generation (the messages' text, "
        "without the chat template's own tokens).",
    ]
    if examples:
        lines += ["", "| Pattern | Level | Instruction | Passed | Failed checks |", "| --- | ---: | --- | --- | --- |"]
        for row in examples:
            check = row["verification"]
            lines.append(
                f"| {row['pattern']} | {row['level']} | {_cell(str(row['instruction']))} | "
                f"{'yes' if check['passed'] else 'no'} (attempt {check['attempts']}) | "
                f"{_cell(', '.join(check['failed_checks'])) or '-'} |"
            )
    return "\n".join(lines)


def sample_card_section(stats: Mapping[str, Any], root: Path) -> str:
    """The card's LLM fragment: an LLM build's own statistics when it has them, else the committed sample's
    summary under `root`, else a line saying none was measured."""
    if "generation" in stats:
        return card_section(stats["generation"], "Measured on this build.")
    path = root / SAMPLE_SUMMARY
    if not path.is_file():
        return "### What `talkdem build --generator llm` gives and costs\n\nNot measured for this revision."
    summary = json.loads(path.read_text(encoding="utf-8"))
    # one example row per pattern (the summary keeps up to three)
    shown = list({row["pattern"]: row for row in reversed(summary.get("examples", []))}.values())[::-1]
    return card_section(summary["stats"], summary["context"], shown)
