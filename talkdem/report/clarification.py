"""The report's clarification section: one table, present only when a run asked questions.

Each clarification run is paired with the run in the report that planned the same episodes without it
(same model, planner and strategy; `clarify` none): success gained per question and the change in success
are measured on the episodes both runs have, paired by id: per episode, success with minus without
clarification, tested with standard errors clustered by task (the plan-length table's test). A group of one
episode per task (one pattern and level) makes that exactly the paired t-test over tasks the report uses
elsewhere; where a task has several episodes (a pattern over its levels, all conditions) they are not taken
as independent.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from talkdem.metrics import CLARIFICATION_GROUPS, clarification_scores, clustered_mean_test, stars
from talkdem.report.runs import ScoredRun
from talkdem.report.table import Table
from talkdem.runs.records import EpisodeRecord
from talkdem.schema import PATTERNS

__all__ = ["clarification_table", "paired_without"]


def _same_planning(a: ScoredRun, b: ScoredRun) -> bool:
    return (a.header.model, a.header.planner, a.header.strategy, a.header.dataset_hash) == (
        b.header.model,
        b.header.planner,
        b.header.strategy,
        b.header.dataset_hash,
    )


def paired_without(run: ScoredRun, runs: Sequence[ScoredRun]) -> ScoredRun | None:
    """The first run of `runs` that plans like `run` but without clarification (None if there is none)."""
    return next((r for r in runs if r.clarify == "none" and _same_planning(run, r)), None)


def _pct(value: float) -> str:
    return "–" if math.isnan(value) else f"{100 * value:.1f}"


def _number(value: float) -> str:
    return "–" if math.isnan(value) else f"{value:.2f}"


def _group_label(group: str) -> str:
    pattern, _, level = group.partition(":")
    name = PATTERNS[pattern].abbreviation if pattern in PATTERNS else pattern
    return f"{name} L{level}" if level else name


def _in_group(record: EpisodeRecord, group: str) -> bool:
    return group == "all" or group in (record.pattern, f"{record.pattern}:{record.level}")


def _change(records: Sequence[EpisodeRecord], without: dict[str, bool], group: str) -> str:
    """The change in SR (points) on the paired episodes of `group`, starred by the task-clustered test."""
    chosen = [r for r in records if _in_group(r, group) and r.episode_id in without]
    if not chosen:
        return "–"
    differences = [float(r.success) - float(without[r.episode_id]) for r in chosen]
    test = clustered_mean_test(differences, [r.task_id for r in chosen])
    return f"{100 * test.mean_difference:+.1f}{stars(test.p_value)}"


def _flips(flips: tuple[int, int] | None) -> str:
    return "–" if flips is None else f"+{flips[0]}/−{flips[1]}"


def clarification_table(runs: Sequence[ScoredRun]) -> Table | None:
    """Clarification per run and group (None when no run of the report asked questions)."""
    from talkdem.runs.store import read_episodes

    rows: list[tuple[str, ...]] = []
    for run in runs:
        if run.clarify == "none":
            continue
        records = read_episodes(run.run_dir)
        other = paired_without(run, runs)
        baseline = read_episodes(other.run_dir) if other is not None else None
        scores = clarification_scores(records, baseline)
        if scores is None:
            continue
        without = {r.episode_id: r.success for r in baseline or ()}
        for group in CLARIFICATION_GROUPS:
            row = scores.rows.get(group)
            if row is None:
                continue
            rows.append(
                (
                    run.label,
                    run.clarify,
                    _group_label(group),
                    str(row.episodes),
                    _pct(row.success_rate),
                    _change(records, without, group) if baseline is not None else "–",
                    _number(row.questions_per_episode),
                    _pct(row.help_rate),
                    _number(100 * row.gain_per_question) if not math.isnan(row.gain_per_question) else "–",
                    _pct(row.retention),
                    _flips(row.flips_when_asked),
                    _flips(row.flips_without_asking),
                    str(scores.unneeded_questions) if group == "clean" else "",
                )
            )
    if not rows:
        return None
    return Table(
        "clarification",
        "Asking before acting: clarification per pattern and level",
        "Runs whose planner could ask (answers: oracle, clear; in-pattern, spoken under the instruction's own "
        "pattern and level). SR (%) with clarification; its change (points) against the same model, planner and "
        "strategy without clarification, on the episodes both have, with a two-sided t-test on the paired "
        "differences, standard errors clustered by task (*p<0.05, **p<0.01, ***p<0.001); questions per "
        "episode; help rate (% of episodes with a question); "
        "success gained per question (points per question asked); clean-conditioned retention (%) with "
        "clarification; flips: paired episodes that succeed only with clarification (+) or only without (−), "
        "among those that asked a question and those that asked none (offering the questions changes the "
        "prompt, so episodes that ask nothing can change too: only the flips after asking are the questions' "
        "doing); unneeded questions: asked on clean instructions.",
        (
            "Run",
            "Answers",
            "Group",
            "n",
            "SR",
            "ΔSR vs none",
            "Questions/ep",
            "Help rate",
            "Gain/question",
            "Retention",
            "Flips, asked",
            "Flips, not asked",
            "Unneeded",
        ),
        tuple(rows),
    )
