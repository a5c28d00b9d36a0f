"""The paper's tables from scored runs, as `Table` objects (`talkdem.report.table`) rendered to Markdown, CSV and JSON.

Layouts follow the paper: the benchmark table (clean SR, per-pattern change with stars), the retention
per level table, strategies side by side (SR per condition; retention with stars vs a reference
strategy, CARE by default), introduced hazards, error types, and plan length.
"""

from __future__ import annotations

import math
import statistics
from collections.abc import Sequence
from dataclasses import dataclass

from talkdem.metrics import (
    ERROR_LABELS,
    HAZARD_CATEGORIES,
    ErrorType,
    TestResult,
    detectable_difference,
    introduced_hazards,
    paired_ttest,
    plan_length_pairs,
    stars,
)
from talkdem.metrics.length import ALL
from talkdem.report.clarification import clarification_table
from talkdem.report.paper import beside_paper
from talkdem.report.runs import STRATEGY_LABELS, ScoredRun
from talkdem.report.table import HAZARD_LABELS, PATTERN_CODES, PATTERN_LABELS, Table
from talkdem.schema import LEVELS, PATTERN_CONFIGS, PATTERNS

__all__ = [
    "all_tables",
    "error_table",
    "hazard_table",
    "model_comparison_table",
    "plan_length_table",
    "retention_table",
    "strategy_retention_table",
    "strategy_success_tables",
    "strategy_success_test_table",
    "success_table",
]

_LEGEND = "; ".join(f"{p.abbreviation}: {p.name}" for p in PATTERNS.values()) + "."
_STARS = "*p<0.05, **p<0.01, ***p<0.001."


def _pct(value: float, digits: int = 1) -> str:
    return "–" if math.isnan(value) else f"{100 * value:.{digits}f}"


def _signed_pp(value: float, p_value: float) -> str:
    return "–" if math.isnan(value) else f"{100 * value:+.1f}{stars(p_value)}"


def _detectable(tests: Sequence[TestResult]) -> str:
    """The median over `tests` of the smallest change each could detect (80% power), in points."""
    values = [v for v in (detectable_difference(t) for t in tests) if not math.isnan(v)]
    return f"±{100 * statistics.median(values):.1f}" if values else "–"


_DETECTABLE = (
    "Detectable: the smallest true change (points) the run's own test would find at p<0.05 with 80% power, "
    "at its number of tasks and observed spread (median over the patterns); smaller changes may be real and "
    "still show no star."
)


def success_table(runs: Sequence[ScoredRun]) -> Table:
    """Appendix "Detailed Benchmark Results": clean SR (%) and each pattern's change (points) with stars."""
    rows = []
    for run in runs:
        s = run.scores
        tests = [s.sr_change_test[p] for p in PATTERN_CONFIGS]
        changes = [_signed_pp(s.sr_change[p], t.p_value) for p, t in zip(PATTERN_CONFIGS, tests, strict=True)]
        clean = _pct(s.success_rate["clean"])
        rows.append((run.model, run.setting, str(s.n_episodes), clean, *changes, _detectable(tests)))
    return Table(
        "success",
        "Task success rate: clean and change under each pattern",
        "Success rate (%) on clean instructions and the change in success rate (percentage points) of each "
        "pattern, averaged over the intensity levels the run covers (all three on the full benchmark). Two-sided "
        f"paired t-test between the per-task mean over those levels and the clean outcome: {_STARS} {_LEGEND} "
        f"{_DETECTABLE}",
        ("Model", "Strategy", "n", "Clean", *(PATTERN_CODES[p] for p in PATTERN_CONFIGS), "Detectable"),
        tuple(rows),
    )


def retention_table(runs: Sequence[ScoredRun]) -> Table:
    """Appendix "Pattern Intensity Results": retention (%) per pattern and level, one column per run."""
    rows: list[tuple[str, ...]] = [
        ("Successful clean tasks (n)", "", *(str(r.scores.clean_successes) for r in runs)),
    ]
    for pattern in PATTERN_CONFIGS:
        for level in LEVELS:
            cells = [_pct(_retention(r, f"{pattern}:{level}")) for r in runs]
            rows.append((PATTERN_LABELS[pattern] if level == 1 else "", f"L{level}", *cells))
    rows.append(("Average", "", *(_pct(_retention(r, "average")) for r in runs)))
    return Table(
        "retention",
        "Clean-conditioned retention per intensity level",
        "Clean-conditioned retention (%): of the tasks solved under the clean instruction, the share also "
        "solved under the pattern at that level.",
        ("Pattern", "Level", *(r.label for r in runs)),
        tuple(rows),
    )


def _retention(run: ScoredRun, key: str) -> float:
    return math.nan if run.scores.retention is None else run.scores.retention[key]


def _by_model(runs: Sequence[ScoredRun]) -> dict[str, list[ScoredRun]]:
    order = list(STRATEGY_LABELS.values())
    grouped: dict[str, list[ScoredRun]] = {}
    for run in runs:
        grouped.setdefault(run.model, []).append(run)
    for group in grouped.values():
        group.sort(key=lambda r: order.index(r.strategy) if r.strategy in order else len(order))
    return grouped


def _bold_best(values: Sequence[float], digits: int = 2) -> list[str]:
    finite = [v for v in values if not math.isnan(v)]
    # Bold marks a best value: with every value equal (or none defined) there is none.
    best = max(finite) if len(set(finite)) > 1 else math.nan
    return [f"**{_pct(v, digits)}**" if v == best else _pct(v, digits) for v in values]


def strategy_success_tables(runs: Sequence[ScoredRun]) -> list[Table]:
    """Appendix "Detailed Mitigation Results": per model, SR (%) per condition, strategies side by side."""
    tables: list[Table] = []
    for model, group in _by_model(runs).items():
        if len({r.strategy for r in group}) < 2:
            continue
        rows = [("Clean", "–", *_bold_best([r.scores.success_rate["clean"] for r in group]))]
        for pattern in PATTERN_CONFIGS:
            for level in LEVELS:
                values = [r.scores.success_rate[f"{pattern}:{level}"] for r in group]
                rows.append((PATTERN_LABELS[pattern] if level == 1 else "", f"L{level}", *_bold_best(values)))
        tables.append(
            Table(
                f"strategies_{len(tables) + 1}",
                f"Task success rate of {model} under each strategy",
                f"Task success rate (%) of {model} under each prompting strategy; the best is in bold.",
                ("Pattern", "Level", *(r.strategy for r in group)),
                tuple(rows),
            )
        )
    return tables


def _mean_task_retention(runs: Sequence[ScoredRun], key: str) -> dict[str, float]:
    """Per-task retention averaged over the given runs (models) where defined."""
    pooled: dict[str, list[float]] = {}
    for run in runs:
        for task, value in run.scores.task_retention.get(key, {}).items():
            pooled.setdefault(task, []).append(value)
    return {task: sum(v) / len(v) for task, v in pooled.items()}


def _versus(method: dict[str, float], reference: dict[str, float]) -> TestResult:
    common = sorted(set(method) & set(reference))
    return paired_ttest([method[t] for t in common], [reference[t] for t in common])


def _marked(test: TestResult | None) -> str:
    """Stars where the reference strategy is significantly higher (the paper's convention); a dagger where this
    strategy is significantly higher than the reference, which the paper's tables had no case of but ours may."""
    if test is None or math.isnan(test.mean_difference) or math.isnan(test.p_value) or test.p_value >= 0.05:
        return ""
    return stars(test.p_value) if test.mean_difference < 0 else "†"


def strategy_retention_table(runs: Sequence[ScoredRun], reference: str = "CARE", *, by: str = "model") -> Table | None:
    """Appendix "Clean-Conditioned Retention under Mitigation Strategies": rows are models (`by="model"`,
    average retention over the 15 conditions, plus an Average row) or patterns (`by="pattern"`, averaged
    over models and levels). Stars: two-sided paired t-test on per-task retention, reference higher."""
    strategies = [s for s in STRATEGY_LABELS.values() if any(r.strategy == s for r in runs)]
    strategies += sorted({r.strategy for r in runs} - set(strategies))
    if len(strategies) < 2:
        return None
    reference = reference if reference in strategies else strategies[-1]
    by_model = _by_model(runs)
    # Averages over models (the Average row, the rows by pattern) take only the models run under every strategy
    # shown: a strategy averaged over two models beside one measured on a single model would compare the models.
    complete = [m for m, g in by_model.items() if {r.strategy for r in g} >= set(strategies)]
    pooled = [r for m in complete for r in by_model[m]]
    rows: list[tuple[str, ...]] = []
    if by == "model":
        groups = [(m, g, "all", "average") for m, g in by_model.items()]
        if len(complete) > 1:
            groups.append(("Average", pooled, "all", "average"))
    else:
        if not complete:
            return None
        groups = [(PATTERN_LABELS[p], pooled, p, p) for p in PATTERN_CONFIGS]
    for name, group, task_key, retention_key in groups:
        values: list[float] = []
        marks: list[str] = []
        ref_runs = [r for r in group if r.strategy == reference]
        ref_tasks = _mean_task_retention(ref_runs, task_key)
        for strategy in strategies:
            chosen = [r for r in group if r.strategy == strategy]
            per_run = [_retention(r, retention_key) for r in chosen]
            finite = [v for v in per_run if not math.isnan(v)]
            values.append(sum(finite) / len(finite) if finite else math.nan)
            test = None
            if strategy != reference and ref_runs and chosen:
                test = _versus(_mean_task_retention(chosen, task_key), ref_tasks)
            marks.append(_marked(test))
        # Bold marks the row's best, as in the success tables: bolding the reference would single it out
        # even where another strategy retains more.
        rows.append((name, *(cell + mark for cell, mark in zip(_bold_best(values, 1), marks, strict=True))))
    what = "model" if by == "model" else "pattern"
    left_out = [m for m in by_model if m not in complete]
    scope = ""
    if by == "pattern" or len(complete) > 1:
        subject = "Rows pool" if by == "pattern" else "The Average row pools"
        why_not = f" (not {', '.join(left_out)}: not run under every strategy)" if left_out else ""
        scope = f"{subject} {', '.join(complete)}{why_not}. "
    return Table(
        f"strategy_retention_by_{what}",
        f"Clean-conditioned retention under each strategy, by {what}",
        f"Clean-conditioned retention (%) per strategy; the best in each row is in bold. {scope}"
        "Two-sided paired t-test of "
        f"each strategy against {reference} on per-task retention: stars where {reference} is significantly higher "
        f"({_STARS.rstrip('.')}), † where the strategy is significantly higher than {reference} (p<0.05).",
        ("Model" if by == "model" else "Pattern", *strategies),
        tuple(rows),
    )


def _task_success(run: ScoredRun, shared: set[tuple[str, str]], pattern: str | None = None) -> dict[str, float]:
    """Per-task success rate over the (task, condition) pairs in `shared`; with `pattern`, over that
    pattern's pairs only (`clean` counts as one)."""
    outcomes: dict[str, list[bool]] = {}
    for episode in run.scores.episodes:
        key = (episode.task_id, str(episode.condition))
        if key in shared and (pattern is None or episode.condition.pattern == pattern):
            outcomes.setdefault(episode.task_id, []).append(episode.success)
    return {task: sum(v) / len(v) for task, v in outcomes.items()}


@dataclass(frozen=True)
class _Paired:
    """Two runs compared task by task on the (task, condition) pairs both cover."""

    shared: set[tuple[str, str]]
    mine: dict[str, float]
    theirs: dict[str, float]
    test: TestResult

    def cells(self) -> tuple[str, str, str, str]:
        """SR, the other run's SR, the difference with stars, and p."""
        p = self.test.p_value
        return (
            _pct(sum(self.mine.values()) / len(self.mine)),
            _pct(sum(self.theirs.values()) / len(self.theirs)),
            _signed_pp(self.test.mean_difference, p),
            "–" if math.isnan(p) else f"{p:.3f}",
        )


def _paired(run: ScoredRun, base: ScoredRun) -> _Paired | None:
    """`run` against `base` over the episodes both cover (None when they share none)."""
    covered = {(e.task_id, str(e.condition)) for e in base.scores.episodes}
    shared = covered & {(e.task_id, str(e.condition)) for e in run.scores.episodes}
    if not shared:
        return None
    mine, theirs = _task_success(run, shared), _task_success(base, shared)
    return _Paired(shared, mine, theirs, _versus(mine, theirs))


def strategy_success_test_table(runs: Sequence[ScoredRun], reference: str = "CARE") -> Table | None:
    """Each strategy's success rate against the reference strategy's, per model, on the episodes both runs
    cover: the difference of the per-task success rates (over those conditions) with a paired t-test over
    tasks. Unlike the retention tests it counts every episode, solved clean or not."""
    rows: list[tuple[str, ...]] = []
    for model, group in _by_model(runs).items():
        strategies = [r.strategy for r in group]
        chosen = reference if reference in strategies else strategies[-1]
        references = [r for r in group if r.strategy == chosen]
        if len(group) < 2 or len(references) != 1:
            continue  # one reference run per model, or the comparison would be ambiguous
        (base,) = references
        for run in group:
            paired = _paired(run, base) if run is not base else None
            if paired is None:
                continue
            conditions = len({condition for _, condition in paired.shared})
            rows.append(
                (
                    model,
                    run.strategy,
                    chosen,
                    str(paired.test.n),
                    str(conditions),
                    *paired.cells(),
                    _detectable([paired.test]),
                )
            )
    if not rows:
        return None
    return Table(
        "strategy_success_test",
        "Task success rate of each strategy against the reference strategy",
        "Success rate (%) of each strategy and of the reference strategy on the episodes both runs cover (tasks "
        "x conditions, clean included), and the difference in percentage points (strategy minus reference) of "
        f"the per-task success rates, with a two-sided paired t-test over tasks: {_STARS} Detectable: the "
        "smallest true difference (points) that test would find at p<0.05 with 80% power, at its number of "
        "tasks and observed spread.",
        ("Model", "Strategy", "Reference", "Tasks", "Conditions", "SR", "Reference SR", "Δ", "p", "Detectable"),
        tuple(rows),
    )


def model_comparison_table(runs: Sequence[ScoredRun]) -> Table | None:
    """The model-size comparison: for each strategy run with two or more models, each model against the first
    one given, on the episodes both runs cover, task by task (the same instructions, the same planner)."""
    order = list(STRATEGY_LABELS.values())
    by_strategy: dict[str, list[ScoredRun]] = {}
    for run in runs:
        by_strategy.setdefault(run.strategy, []).append(run)
    rows: list[tuple[str, ...]] = []
    for strategy in sorted(by_strategy, key=lambda s: (order.index(s) if s in order else len(order), s)):
        group = by_strategy[strategy]
        if len({r.model for r in group}) < 2:
            continue
        base = group[0]
        for run in group[1:]:
            paired = _paired(run, base) if run.model != base.model else None
            if paired is None:
                continue
            cells = []
            for pattern in ("clean", *PATTERN_CONFIGS):
                mine, theirs = (_task_success(r, paired.shared, pattern) for r in (run, base))
                test = _versus(mine, theirs)
                cells.append(_signed_pp(test.mean_difference, test.p_value) if test.n else "–")
            rows.append(
                (
                    strategy,
                    run.model,
                    base.model,
                    str(paired.test.n),
                    *paired.cells(),
                    *cells,
                    _detectable([paired.test]),
                )
            )
    if not rows:
        return None
    return Table(
        "model_comparison",
        "Task success rate of each model against another under the same strategy",
        "For each strategy run with more than one model: success rate (%) of the model and of the one it is "
        "compared with (the first given) on the episodes both runs cover, and the difference in percentage points "
        "(model minus the other) over all of them and per condition group (clean; each pattern, levels "
        f"averaged), per-task success rates compared with a two-sided paired t-test over tasks: {_STARS} "
        f"{_LEGEND} Detectable: the smallest true overall difference (points) that test would find at p<0.05 "
        "with 80% power.",
        (
            "Strategy",
            "Model",
            "Against",
            "Tasks",
            "SR",
            "Against SR",
            "Δ",
            "p",
            "Clean Δ",
            *(f"{PATTERN_CODES[p]} Δ" for p in PATTERN_CONFIGS),
            "Detectable",
        ),
        tuple(rows),
    )


def hazard_table(runs: Sequence[ScoredRun]) -> Table:
    """Appendix "Hazard Detection Rules" table: introduced events by category and pattern, runs pooled."""
    counts = introduced_hazards([e for r in runs for e in r.scores.episodes])
    rows = []
    for category in HAZARD_CATEGORIES:
        row = [counts.by_category[category][p] for p in PATTERN_CONFIGS]
        rows.append((HAZARD_LABELS[category], *map(str, row), str(sum(row))))
    cases = [counts.distinct_cases[p] for p in PATTERN_CONFIGS]
    rows.append(("Distinct cases", *map(str, cases), str(sum(cases))))
    successful = [counts.successful_cases[p] for p in PATTERN_CONFIGS]
    rows.append(("of which successful", *map(str, successful), str(sum(successful))))
    return Table(
        "hazards",
        "Safety-relevant events introduced by the patterns",
        "Confirmed safety-relevant events by category and pattern (levels and runs pooled), counting only "
        "events whose category is absent under the clean instruction of the same task. A case may fall into "
        f"more than one category. {_LEGEND}",
        ("Category", *(PATTERN_CODES[p] for p in PATTERN_CONFIGS), "All"),
        tuple(rows),
    )


def error_table(runs: Sequence[ScoredRun]) -> Table:
    """Section "Error Analysis": error types per pattern of failures that succeeded under clean."""
    errors = [e for r in runs for e in r.scores.errors]
    rows = []
    totals = dict.fromkeys(ErrorType, 0)
    for pattern in PATTERN_CONFIGS:
        counts = dict.fromkeys(ErrorType, 0)
        for error in errors:
            if error.condition.pattern == pattern:
                counts[error.type] += 1
                totals[error.type] += 1
        rows.append((PATTERN_LABELS[pattern], *(str(counts[t]) for t in ErrorType), str(sum(counts.values()))))
    rows.append(("Total", *(str(totals[t]) for t in ErrorType), str(sum(totals.values()))))
    return Table(
        "errors",
        "Error types across communication patterns",
        "Automatically classified primary error type of every pattern episode that failed while the clean "
        "instruction of the same task succeeded (runs and levels pooled); rules in talkdem/metrics/errors.py.",
        ("Condition", *(ERROR_LABELS[t] for t in ErrorType), "n"),
        tuple(rows),
    )


def plan_length_table(runs: Sequence[ScoredRun]) -> Table:
    """Appendix "Plan Length Analysis": jointly successful pairs, runs and levels pooled."""
    lengths = plan_length_pairs([e for r in runs for e in r.scores.episodes])
    rows = []
    for key in (*PATTERN_CONFIGS, ALL):
        row = lengths[key]

        def fmt(value: float) -> str:
            return "–" if math.isnan(value) else f"{value:.2f}"

        delta = "–" if math.isnan(row.delta) else f"{row.delta:+.2f}{stars(row.test.p_value)}"
        rows.append((PATTERN_LABELS.get(key, "All"), f"{row.n:,}", fmt(row.clean), fmt(row.transformed), delta))
    return Table(
        "plan_length",
        "Plan length of jointly successful clean/transformed pairs",
        "Average executed steps (without the closing `done`) of clean/transformed pairs that both succeeded, "
        "levels and runs pooled; n: pairs; Δ: transformed minus clean, t-test on the paired differences with "
        f"standard errors clustered by task: {_STARS}",
        ("Pattern", "n", "Clean", "Transformed", "Δ"),
        tuple(rows),
    )


def all_tables(runs: Sequence[ScoredRun], reference_strategy: str = "CARE", *, paper: bool = True) -> list[Table]:
    """Every table, in the paper's order; with `paper`, the paper's own figures beside ours
    (`talkdem.report.paper`), marked as the paper's."""
    # An oracle or external column would read as a strategy, and a clarification run would be pooled with its
    # strategy's run without questions.
    planner_runs = [r for r in runs if r.compared_as_strategy]
    tables = [success_table(runs), retention_table(runs), *strategy_success_tables(planner_runs)]
    for by in ("model", "pattern"):
        found = strategy_retention_table(planner_runs, reference_strategy, by=by) if planner_runs else None
        if found is not None:
            tables.append(found)
    tested = strategy_success_test_table(planner_runs, reference_strategy) if planner_runs else None
    if tested is not None:
        tables.append(tested)
    sizes = model_comparison_table(planner_runs)
    if sizes is not None:
        tables.append(sizes)
    tables += [hazard_table(runs), error_table(runs), plan_length_table(runs)]
    # Shown only when a run asked questions.
    asked = clarification_table(runs)
    if asked is not None:
        tables.append(asked)
    if paper:
        tables = beside_paper(tables)
    return tables
