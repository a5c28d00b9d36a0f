"""Clarification metrics: what asking cost and bought, per condition, pattern and overall.

Read from episode records whose trace holds the dialogue (`trace["dialogue"]`, written in clarification
mode; a run without it has no clarification metrics). Groups: `all`, `clean`, each pattern (its three
levels pooled) and each `pattern:level`.

- success rate with clarification: successes / episodes of the group;
- questions per episode: questions asked / episodes; help rate: the share of episodes with at least one
  question (KnowNo's help rate);
- success gained per question (only with a paired run without clarification): over the episodes both runs
  have (paired by id), (SR here - SR there) / questions per episode here; undefined when nothing was asked;
- unneeded questions: questions asked on clean instructions (a clear request needs none), in all and per
  clean episode;
- clean-conditioned retention with clarification, as the benchmark defines it (`talkdem.metrics.rates`):
  of a `pattern:level`, among tasks solved under clean and evaluated under it, the share also solved; of a
  pattern, the mean over its levels; of `all`, the mean over the 15 conditions.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, Protocol

from talkdem.schema import CLEAN, CONDITIONS, LEVELS, PATTERN_CONFIGS, parse_instruction_id


class EpisodeRecord(Protocol):
    """What these measures read of an episode (`talkdem.runs.EpisodeRecord` has it)."""

    @property
    def episode_id(self) -> str: ...
    @property
    def task_id(self) -> str: ...
    @property
    def pattern(self) -> str: ...
    @property
    def level(self) -> int: ...
    @property
    def success(self) -> bool: ...
    @property
    def trace(self) -> dict[str, Any]: ...


@dataclass(frozen=True)
class _Outcome:
    episode_id: str
    task_id: str
    pattern: str
    level: int
    success: bool
    trace: dict[str, Any] = field(default_factory=dict)


__all__ = [
    "CLARIFICATION_GROUPS",
    "ClarificationRow",
    "ClarificationScores",
    "asked_questions",
    "clarification_from_outcomes",
    "clarification_scores",
    "used_clarification",
]

CLARIFICATION_GROUPS: tuple[str, ...] = (
    "all",
    CLEAN,
    *PATTERN_CONFIGS,
    *(str(c) for c in CONDITIONS[1:]),
)
"""The groups of `ClarificationScores.rows`, in the order tables show them."""


@dataclass(frozen=True)
class ClarificationRow:
    """The clarification measures of one group of episodes."""

    group: str
    episodes: int
    success_rate: float
    questions_per_episode: float
    help_rate: float
    """Episodes with at least one question / episodes."""
    gain_per_question: float
    """(SR with clarification - SR of the paired run) / questions per episode; NaN without a paired run or
    without questions."""
    retention: float
    """Clean-conditioned retention with clarification (NaN for `clean` and for groups without clean pairs)."""
    flips_when_asked: tuple[int, int] | None = None
    """(gained, lost): paired episodes with at least one question that succeeded where the run without
    clarification failed, and the reverse; None without a paired run."""
    flips_without_asking: tuple[int, int] | None = None
    """The same for paired episodes that asked nothing. Offering questions changes the prompt, so these move
    too: only the flips when asked can be put down to the questions and their answers."""


@dataclass(frozen=True)
class ClarificationScores:
    rows: dict[str, ClarificationRow]
    unneeded_questions: int
    """Questions asked on clean instructions."""
    unneeded_per_clean_episode: float
    paired: bool
    """Whether a run without clarification was given (`gain_per_question` is defined only then)."""

    def flat(self) -> dict[str, float]:
        """`clarify/<measure>/<group>` -> value, and the two unneeded-question counts."""
        out: dict[str, float] = {}
        for group, row in self.rows.items():
            out[f"clarify/sr/{group}"] = row.success_rate
            out[f"clarify/questions/{group}"] = row.questions_per_episode
            out[f"clarify/help_rate/{group}"] = row.help_rate
            out[f"clarify/gain_per_question/{group}"] = row.gain_per_question
            out[f"clarify/retention/{group}"] = row.retention
            for name, flips in (("when_asked", row.flips_when_asked), ("without_asking", row.flips_without_asking)):
                gained, lost = flips if flips is not None else (math.nan, math.nan)
                out[f"clarify/gained_{name}/{group}"] = float(gained)
                out[f"clarify/lost_{name}/{group}"] = float(lost)
        out["clarify/unneeded_questions"] = float(self.unneeded_questions)
        out["clarify/unneeded_per_clean_episode"] = self.unneeded_per_clean_episode
        return out


def used_clarification(records: Sequence[EpisodeRecord]) -> bool:
    """Whether the episodes were planned in clarification mode (their traces hold a dialogue)."""
    return any("dialogue" in record.trace for record in records)


def asked_questions(record: EpisodeRecord) -> int:
    """Questions asked in one episode (0 when its trace holds no dialogue)."""
    dialogue = record.trace.get("dialogue", [])
    return len(dialogue) if isinstance(dialogue, list) else 0


def _groups(record: EpisodeRecord) -> tuple[str, ...]:
    if record.pattern == CLEAN:
        return ("all", CLEAN)
    return ("all", record.pattern, f"{record.pattern}:{record.level}")


def _mean(values: Sequence[float]) -> float:
    defined = [v for v in values if not math.isnan(v)]
    return sum(defined) / len(defined) if defined else math.nan


def _retention(records: Sequence[EpisodeRecord]) -> dict[str, float]:
    clean = {r.task_id for r in records if r.pattern == CLEAN and r.success}
    out: dict[str, float] = {}
    for pattern in PATTERN_CONFIGS:
        for level in LEVELS:
            kept = [r.success for r in records if (r.pattern, r.level) == (pattern, level) and r.task_id in clean]
            out[f"{pattern}:{level}"] = sum(kept) / len(kept) if kept else math.nan
        out[pattern] = _mean([out[f"{pattern}:{level}"] for level in LEVELS])
    out["all"] = _mean([out[f"{p}:{lvl}"] for p in PATTERN_CONFIGS for lvl in LEVELS])
    return out


def _flips(records: Sequence[EpisodeRecord], baseline: Mapping[str, bool]) -> tuple[int, int]:
    """(gained, lost): of `records`, those that succeed where their pair in `baseline` fails, and the reverse."""
    gained = sum(r.success and not baseline[r.episode_id] for r in records)
    lost = sum(baseline[r.episode_id] and not r.success for r in records)
    return gained, lost


def clarification_scores(
    records: Sequence[EpisodeRecord], without: Sequence[EpisodeRecord] | None = None
) -> ClarificationScores | None:
    """The clarification measures of a run's episodes (None when the run did not use clarification);
    `without`: the same episodes planned without clarification, paired by episode id."""
    if not used_clarification(records):
        return None
    baseline: Mapping[str, bool] = {r.episode_id: r.success for r in without or ()}
    members: dict[str, list[EpisodeRecord]] = {group: [] for group in CLARIFICATION_GROUPS}
    for record in records:
        for group in _groups(record):
            members.setdefault(group, []).append(record)
    retention = _retention(records)
    rows = {}
    for group, chosen in members.items():
        if not chosen:
            continue
        n = len(chosen)
        questions = [asked_questions(r) for r in chosen]
        gain = math.nan
        paired = [(r, q) for r, q in zip(chosen, questions, strict=True) if r.episode_id in baseline]
        asked = sum(q for _, q in paired) / len(paired) if paired else 0.0
        if paired and asked > 0:
            change = sum(r.success - baseline[r.episode_id] for r, _ in paired) / len(paired)
            gain = change / asked
        rows[group] = ClarificationRow(
            group=group,
            episodes=n,
            success_rate=sum(r.success for r in chosen) / n,
            questions_per_episode=sum(questions) / n,
            help_rate=sum(q > 0 for q in questions) / n,
            gain_per_question=gain,
            retention=retention.get(group, math.nan),
            flips_when_asked=_flips([r for r, q in paired if q > 0], baseline) if without is not None else None,
            flips_without_asking=_flips([r for r, q in paired if q == 0], baseline) if without is not None else None,
        )
    clean = [asked_questions(r) for r in records if r.pattern == CLEAN]
    return ClarificationScores(
        rows=rows,
        unneeded_questions=sum(clean),
        unneeded_per_clean_episode=sum(clean) / len(clean) if clean else math.nan,
        paired=without is not None,
    )


def _outcome(episode_id: str, success: bool, questions: int | None) -> _Outcome:
    task_id, condition = parse_instruction_id(episode_id)
    trace: dict[str, Any] = {} if questions is None else {"dialogue": [{}] * questions}
    return _Outcome(episode_id, task_id, condition.pattern, condition.level, success, trace)


def clarification_from_outcomes(
    successes: Mapping[str, bool], questions: Mapping[str, int], without: Mapping[str, bool] | None = None
) -> ClarificationScores | None:
    """`clarification_scores` from outcomes and question counts by instruction id (the `evaluate` metric's
    inputs); `without`: success without clarification by id."""
    missing = sorted(set(successes) - set(questions))
    if missing:
        raise ValueError(f"question counts are missing for: {', '.join(missing[:5])}")
    if any(not isinstance(n, int) or isinstance(n, bool) or n < 0 for n in questions.values()):
        raise ValueError("question counts must be non-negative integers")
    records = [_outcome(i, s, questions[i]) for i, s in successes.items()]
    baseline = None if without is None else [_outcome(i, s, None) for i, s in without.items()]
    return clarification_scores(records, baseline)
