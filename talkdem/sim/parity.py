"""The parity suite: perturbed reference plans with stored verdicts, replayed on a backend, compared rule by rule.

For every benchmark task, `perturb.py` makes a fixed, seeded set of broken plans. The symbolic backend's
verdicts (goal reached, each step's success, hazards) are stored in `data/parity/cases.jsonl`. Replaying them
on the symbolic backend guards against regressions; replaying them on the AI2-THOR backend measures how often
the simulator decides as the real stack does. Agreement is reported per rule (each skill verb's step
verdicts, the goal, each hazard sub-rule), per task type and per perturbation kind.
"""

from __future__ import annotations

import json
from collections import defaultdict
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from talkdem.seeds.records import SeedTask
from talkdem.sim.executor import PlanExecutor
from talkdem.sim.hazards import HazardRule
from talkdem.sim.parser import parse_skill
from talkdem.sim.perturb import perturb
from talkdem.sim.trace import EpisodeTrace

__all__ = [
    "ParityCase",
    "ParityReport",
    "build_cases",
    "format_report",
    "load_cases",
    "parity_file",
    "replay",
    "write_cases",
]


@dataclass(frozen=True)
class ParityCase:
    """One perturbed plan and the stored verdicts of the backend that built it."""

    case_id: str
    task_id: str
    task_type: str
    kind: str
    plan: tuple[str, ...]
    success: bool
    steps_ok: tuple[bool, ...]
    hazards: tuple[str, ...]
    """Hazard sub-rules flagged (sorted, distinct)."""

    def to_json(self) -> dict[str, object]:
        return {
            "case_id": self.case_id,
            "task_id": self.task_id,
            "task_type": self.task_type,
            "kind": self.kind,
            "plan": list(self.plan),
            "success": self.success,
            "steps_ok": list(self.steps_ok),
            "hazards": list(self.hazards),
        }

    @classmethod
    def from_json(cls, record: dict[str, object]) -> ParityCase:
        try:
            return cls(
                case_id=str(record["case_id"]),
                task_id=str(record["task_id"]),
                task_type=str(record["task_type"]),
                kind=str(record["kind"]),
                plan=tuple(str(s) for s in record["plan"]),  # type: ignore[attr-defined]
                success=bool(record["success"]),
                steps_ok=tuple(bool(s) for s in record["steps_ok"]),  # type: ignore[attr-defined]
                hazards=tuple(str(h) for h in record["hazards"]),  # type: ignore[attr-defined]
            )
        except (KeyError, TypeError) as exc:
            raise ValueError(f"parity case is missing or mistypes a field: {exc}") from None


def parity_file(folder: Path | None = None) -> Path:
    from talkdem.paths import data_dir

    return data_dir(folder) / "parity" / "cases.jsonl"


def _verdicts(trace: EpisodeTrace) -> tuple[bool, tuple[bool, ...], tuple[str, ...]]:
    hazards = tuple(sorted({h.rule.value for h in trace.hazards}))
    return trace.success, tuple(step.ok for step in trace.steps), hazards


def build_cases(tasks: Iterable[SeedTask], executor: PlanExecutor) -> list[ParityCase]:
    """Every task's perturbed plans with `executor`'s verdicts, in task order."""
    cases = []
    for task in tasks:
        for case in perturb(task, getattr(task, "reference_plan", ())):
            success, steps_ok, hazards = _verdicts(executor.run(task, case.plan))
            cases.append(
                ParityCase(
                    case.case_id, task.task_id, task.task_type, case.kind.value, case.plan, success, steps_ok, hazards
                )
            )
    return cases


def write_cases(cases: Sequence[ParityCase], path: Path) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("".join(json.dumps(c.to_json(), ensure_ascii=False) + "\n" for c in cases), encoding="utf-8")


def load_cases(path: Path) -> list[ParityCase]:
    if not path.is_file():
        raise FileNotFoundError(f"{path}: parity cases not found (build them with `talkdem parity --write`)")
    cases = []
    for line_no, line in enumerate(path.read_text(encoding="utf-8").splitlines(), start=1):
        if not line.strip():
            continue
        try:
            cases.append(ParityCase.from_json(json.loads(line)))
        except (ValueError, json.JSONDecodeError) as exc:
            raise ValueError(f"{path}, line {line_no}: {exc}") from None
    return cases


@dataclass
class Tally:
    agree: int = 0
    total: int = 0

    def add(self, same: bool) -> None:
        self.agree += same
        self.total += 1

    @property
    def rate(self) -> float:
        return self.agree / self.total if self.total else 1.0


@dataclass
class ParityReport:
    """Agreement of a replay with the stored verdicts."""

    backend: str
    cases: int = 0
    rules: dict[str, Tally] = field(default_factory=lambda: defaultdict(Tally))
    """`step:<verb>` (each step's success), `goal`, `hazard:<sub-rule>` (flagged or not, per case)."""
    task_types: dict[str, Tally] = field(default_factory=lambda: defaultdict(Tally))
    kinds: dict[str, Tally] = field(default_factory=lambda: defaultdict(Tally))
    disagreements: list[str] = field(default_factory=list)
    """Case ids whose verdicts differ anywhere."""

    @property
    def agreement(self) -> float:
        agree = sum(t.agree for t in self.task_types.values())
        return agree / self.cases if self.cases else 1.0


def _verb(step: str) -> str:
    skill = parse_skill(step)
    return skill.verb.value if skill is not None else "unsupported"


def replay(
    cases: Sequence[ParityCase], tasks: Mapping[str, SeedTask], executor: PlanExecutor, limit: int | None = None
) -> ParityReport:
    """Run each case's plan on `executor` and compare its verdicts with the stored ones."""
    report = ParityReport(backend=executor.name)
    for case in cases[:limit] if limit is not None else cases:
        if case.task_id not in tasks:
            raise ValueError(f"parity case {case.case_id}: task {case.task_id} is not a benchmark task")
        success, steps_ok, hazards = _verdicts(executor.run(tasks[case.task_id], case.plan))
        report.cases += 1
        report.rules["goal"].add(success == case.success)
        for i, step in enumerate(case.plan[: max(len(steps_ok), len(case.steps_ok))]):
            stored = case.steps_ok[i] if i < len(case.steps_ok) else None
            fresh = steps_ok[i] if i < len(steps_ok) else None
            report.rules[f"step:{_verb(step)}"].add(stored == fresh)
        for rule in HazardRule:
            report.rules[f"hazard:{rule.value}"].add((rule.value in hazards) == (rule.value in case.hazards))
        same = (success, steps_ok, hazards) == (case.success, case.steps_ok, case.hazards)
        report.task_types[case.task_type].add(same)
        report.kinds[case.kind].add(same)
        if not same:
            report.disagreements.append(case.case_id)
    return report


def _table(title: str, rows: dict[str, Tally]) -> list[str]:
    lines = [f"| {title} | agree | total | rate |", "|---|---:|---:|---:|"]
    for name in sorted(rows):
        t = rows[name]
        lines.append(f"| {name} | {t.agree} | {t.total} | {t.rate:.3f} |")
    return lines


def format_report(report: ParityReport) -> str:
    """Markdown tables: overall, per rule, per task type, per perturbation kind, then the first disagreements."""
    lines = [
        f"parity: backend {report.backend} vs stored symbolic verdicts, {report.cases} cases, "
        f"whole-case agreement {report.agreement:.3f}",
        "",
        *_table("rule", report.rules),
        "",
        *_table("task type", report.task_types),
        "",
        *_table("perturbation", report.kinds),
    ]
    if report.disagreements:
        shown = ", ".join(report.disagreements[:10])
        more = len(report.disagreements) - 10
        lines += ["", f"disagreeing cases: {shown}" + (f" (+{more} more)" if more > 0 else "")]
    return "\n".join(lines)
