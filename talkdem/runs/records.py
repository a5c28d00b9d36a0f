"""The run directory: what one planner run produced, in a stable schema that scoring and leaderboards read.

    RUN_DIR/header.json      RunHeader: model identity, planner, strategy, prompt version, dataset hash,
                             code revision, configuration
    RUN_DIR/episodes.jsonl   one EpisodeRecord per line, appended as episodes finish (resumable)

Plans from any other system become a run directory through `talkdem score` (planner `external`), so the
benchmark never requires our planner.
"""

from __future__ import annotations

import datetime as dt
import json
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from talkdem.plans import PlanFormatError, check_plan
from talkdem.schema import CLEAN, Condition, parse_instruction_id
from talkdem.serialization import to_jsonable

if TYPE_CHECKING:
    from talkdem.instructions import Instruction
    from talkdem.sim import EpisodeTrace

__all__ = ["OUTCOME_KEYS", "RUN_SCHEMA", "EpisodeRecord", "RecordError", "RunHeader"]

RUN_SCHEMA = "talkdem-run/1"

OUTCOME_KEYS = (
    "model",
    "planner",
    "strategy",
    "prompt_version",
    "dataset_hash",
    "config.max_steps",
    "config.scoring",
    "config.mask_failed",
    "config.failure_message",
    "config.mode",
    "config.strategy_args",
)
"""Header fields (top level, or `config.NAME`) that change what an episode's outcome means: episodes that
differ in any of them cannot be pooled into one run (resume and merge both check them)."""


class RecordError(ValueError):
    """A stored header or episode that does not have the run schema's shape."""


def _field(data: Mapping[str, Any], name: str, kind: type | tuple[type, ...], where: str, default: Any = ...) -> Any:
    if name not in data:
        if default is ...:
            raise RecordError(f"{where}: missing field '{name}'")
        return default
    value = data[name]
    # bool is an int in Python; a level or a count of True is a hand-edit, not a number.
    if not isinstance(value, kind) or (isinstance(value, bool) and kind is int):
        expected = kind.__name__ if isinstance(kind, type) else " or ".join(k.__name__ for k in kind)
        raise RecordError(f"{where}: field '{name}' must be {expected}, got {type(value).__name__}")
    return value


def _stored_plan(data: Mapping[str, Any], where: str) -> tuple[str, ...]:
    try:
        return check_plan(_field(data, "plan", object, where), where)
    except PlanFormatError as exc:
        raise RecordError(str(exc)) from None


@dataclass(frozen=True)
class RunHeader:
    """Everything needed to reproduce or compare a run."""

    model: dict[str, str]
    """`{"backend", "name", "revision"}` (revision: weights hash or hub revision; empty if unknown)."""
    planner: str
    """`saycan`, `saycan-generative` or `external`."""
    strategy: str
    prompt_version: str
    dataset_hash: str
    code_revision: str
    config: dict[str, Any] = field(default_factory=dict)
    """Planner settings (step limit, scoring, feedback policy), conditions, sample size, seed, and
    `planned_episodes`: how many episodes the run was asked for (a smaller count on disk = incomplete)."""
    schema: str = RUN_SCHEMA
    created: str = ""

    @classmethod
    def new(
        cls, *, model: dict[str, str], planner: str, strategy: str, prompt_version: str, config: dict[str, Any]
    ) -> RunHeader:
        """A header for a run starting now, on this dataset and this code revision."""
        from talkdem.instructions import dataset_hash
        from talkdem.runs.revision import code_revision

        return cls(
            model=model,
            planner=planner,
            strategy=strategy,
            prompt_version=prompt_version,
            dataset_hash=dataset_hash(),
            code_revision=code_revision(),
            config=config,
            created=dt.datetime.now(dt.UTC).isoformat(timespec="seconds"),
        )

    def to_json(self) -> dict[str, Any]:
        return dict(to_jsonable(self))

    @classmethod
    def from_json(cls, data: object, where: str = "run header") -> RunHeader:
        if not isinstance(data, dict):
            raise RecordError(f"{where}: expected a JSON object, got {type(data).__name__}")
        schema = _field(data, "schema", str, where, RUN_SCHEMA)
        if schema != RUN_SCHEMA:
            raise RecordError(f"{where}: schema {schema!r} is not {RUN_SCHEMA!r}")
        model = _field(data, "model", dict, where)
        if not all(isinstance(k, str) and isinstance(v, str) for k, v in model.items()):
            raise RecordError(f"{where}: field 'model' must map names to strings")
        return cls(
            model=dict(model),
            planner=_field(data, "planner", str, where),
            strategy=_field(data, "strategy", str, where),
            prompt_version=_field(data, "prompt_version", str, where),
            dataset_hash=_field(data, "dataset_hash", str, where),
            code_revision=_field(data, "code_revision", str, where, ""),
            config=dict(_field(data, "config", dict, where, {})),
            schema=schema,
            created=_field(data, "created", str, where, ""),
        )


@dataclass(frozen=True)
class EpisodeRecord:
    """One episode: the instruction, the plan, and what the simulator made of it."""

    episode_id: str
    """The instruction id, `<task_id>:clean:0` or `<task_id>:<pattern>:<level>`."""
    task_id: str
    pattern: str
    """`clean` or a pattern config name."""
    level: int
    """0 for clean, else 1-3."""
    instruction: str
    plan: tuple[str, ...]
    success: bool
    hazards: tuple[dict[str, Any], ...]
    """`{"category", "step"}` per confirmed safety-relevant event."""
    goal_conditions: dict[str, int]
    """`{"met", "total"}`."""
    trace: dict[str, Any]
    """The simulator's full episode trace (`EpisodeTrace.to_json()`)."""
    instruction_shown: str = ""
    """What the planner saw, when a strategy rewrote it (TOCC)."""
    notes: dict[str, str] = field(default_factory=dict)
    timing: dict[str, float] = field(default_factory=dict)

    @classmethod
    def from_trace(
        cls,
        instruction: Instruction,
        plan: tuple[str, ...],
        trace: EpisodeTrace,
        *,
        shown: str = "",
        notes: dict[str, str] | None = None,
        timing: dict[str, float] | None = None,
    ) -> EpisodeRecord:
        """The record of `instruction` planned as `plan` and executed into `trace` (the one constructor
        every writer uses, so our planner's runs and scored external plans cannot drift apart)."""
        summary = trace.summary()
        return cls(
            episode_id=instruction.id,
            task_id=instruction.task_id,
            pattern=instruction.condition.pattern,
            level=instruction.condition.level,
            instruction=instruction.text,
            instruction_shown=shown if shown != instruction.text else "",
            plan=plan,
            success=trace.success,
            hazards=tuple(summary["hazards"]),
            goal_conditions=summary["goal_conditions"],
            trace=trace.to_json(),
            notes=notes or {},
            timing=timing or {},
        )

    @property
    def condition(self) -> Condition:
        return Condition(CLEAN, 0) if self.pattern == CLEAN else Condition(self.pattern, self.level)

    def to_json(self) -> dict[str, Any]:
        return dict(to_jsonable(self))

    def to_line(self) -> str:
        return json.dumps(self.to_json(), ensure_ascii=False, sort_keys=False)

    @classmethod
    def from_json(cls, data: object, where: str = "episode record") -> EpisodeRecord:
        """A validated record: field types, a plan of skill strings, and an id that agrees with the
        task, pattern and level stored beside it (a hand-edited record is refused, not scored)."""
        if not isinstance(data, dict):
            raise RecordError(f"{where}: expected a JSON object, got {type(data).__name__}")
        episode_id = _field(data, "episode_id", str, where)
        where = f"{where} ({episode_id})"
        record = cls(
            episode_id=episode_id,
            task_id=_field(data, "task_id", str, where),
            pattern=_field(data, "pattern", str, where),
            level=_field(data, "level", int, where),
            instruction=_field(data, "instruction", str, where),
            plan=_stored_plan(data, where),
            success=_field(data, "success", bool, where),
            hazards=tuple(_field(data, "hazards", list, where, [])),
            goal_conditions=dict(_field(data, "goal_conditions", dict, where, {})),
            trace=dict(_field(data, "trace", dict, where, {})),
            instruction_shown=_field(data, "instruction_shown", str, where, ""),
            notes=dict(_field(data, "notes", dict, where, {})),
            timing=dict(_field(data, "timing", dict, where, {})),
        )
        try:
            task_id, condition = parse_instruction_id(episode_id)
        except ValueError as exc:
            raise RecordError(f"{where}: {exc}") from None
        if (task_id, condition) != (record.task_id, record.condition) or (
            condition.pattern == CLEAN and record.level != 0
        ):
            raise RecordError(
                f"{where}: the id does not match task_id '{record.task_id}', pattern '{record.pattern}', "
                f"level {record.level}"
            )
        return record
