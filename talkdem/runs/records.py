"""The run directory: what one planner run produced, in a stable schema that scoring and leaderboards read.

    RUN_DIR/header.json      RunHeader: model identity, planner, strategy, prompt version, dataset hash,
                             code revision, configuration
    RUN_DIR/episodes.jsonl   one EpisodeRecord per line, appended as episodes finish (resumable)

Plans from any other system become a run directory through `talkdem score` (planner `external`), so the
benchmark never requires our planner.
"""

from __future__ import annotations

import dataclasses
import datetime as dt
import functools
import json
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from talkdem.plans import PlanFormatError, check_plan
from talkdem.runs.record_fields import FieldProblem, check_nested_fields
from talkdem.schema import CLEAN, Condition, parse_instruction_id
from talkdem.serialization import to_jsonable

if TYPE_CHECKING:
    from collections.abc import Sequence

    from talkdem.clarify import Exchange
    from talkdem.instructions import Instruction
    from talkdem.sim import EpisodeTrace

__all__ = ["RUN_SCHEMA", "STATUSES", "EpisodeRecord", "RecordError", "RunHeader"]

RUN_SCHEMA = "talkdem-run/1"

STATUSES = ("running", "complete", "incomplete")
"""A run's `status`: being written (or killed while it was), every planned episode on disk, stopped short.
Headers written before the field existed have status "" (unknown: `planned_episodes` still tells)."""


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
    """The code that wrote the latest episodes."""
    config: dict[str, Any] = field(default_factory=dict)
    """Planner settings (every `SayCanConfig` field), `strategy_args`, `backend_args`, conditions, sample
    size, seed, and `planned_episodes`: how many episodes the run was asked for (fewer on disk = incomplete)."""
    schema: str = RUN_SCHEMA
    created: str = ""
    inputs: dict[str, str] = field(default_factory=dict)
    """sha256 of every input file the run reads, by name (`data/tasks/benchmark.jsonl`, ...); empty in
    headers written before inputs were hashed (unknown)."""
    status: str = ""
    """One of `STATUSES`, kept up to date by the writer; "" in older headers (unknown)."""
    code_revisions: tuple[str, ...] = ()
    """Every code revision that wrote episodes, oldest first, when there was more than one (a resume with
    `--continue-on-new-revision`, or a merge of shards run on different revisions)."""
    runtimes: tuple[dict[str, str], ...] = ()
    """Every distinct runtime that wrote episodes (Python, platform, CPU model, the backend's libraries and their
    build: `talkdem.runs.runtime`), in the order first seen; a sitting on the same machine and build adds
    nothing. Empty in headers written before runtimes were recorded, and for runs whose model ran elsewhere."""

    @classmethod
    def new(
        cls,
        *,
        model: dict[str, str],
        planner: str,
        strategy: str,
        prompt_version: str,
        config: dict[str, Any],
        inputs: dict[str, str] | None = None,
        runtime: dict[str, str] | None = None,
    ) -> RunHeader:
        """A header for a run starting now (status `running`), on this dataset and this code revision;
        `runtime`: this sitting's (`talkdem.runs.runtime.sitting_runtime`), when known."""
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
            inputs=dict(inputs or {}),
            status="running",
            runtimes=(dict(runtime),) if runtime else (),
        )

    def with_changes(self, **changes: Any) -> RunHeader:
        return dataclasses.replace(self, **changes)

    def to_json(self) -> dict[str, Any]:
        return dict(to_jsonable(self))

    @classmethod
    def from_json(cls, data: object, where: str = "run header") -> RunHeader:
        """A validated header: every field's type and range (`config.max_steps` a positive integer, a status
        of `STATUSES`, sha256 digests as 64 hex digits, ...); the first bad field is one error naming `where`."""
        if not isinstance(data, dict):
            raise RecordError(f"{where}: expected a JSON object, got {type(data).__name__}")
        schema = _field(data, "schema", str, where, RUN_SCHEMA)
        if schema != RUN_SCHEMA:
            raise RecordError(f"{where}: schema {schema!r} is not {RUN_SCHEMA!r}")
        model = _field(data, "model", dict, where)
        if not all(isinstance(k, str) and isinstance(v, str) for k, v in model.items()):
            raise RecordError(f"{where}: field 'model' must map names to strings")
        dataset = _field(data, "dataset_hash", str, where)
        if dataset and not _is_digest(dataset):
            raise RecordError(f"{where}: field 'dataset_hash' must be a sha256 hex digest (or empty), got {dataset!r}")
        created = _field(data, "created", str, where, "")
        if created:
            try:
                dt.datetime.fromisoformat(created)
            except ValueError:
                raise RecordError(f"{where}: field 'created' must be an ISO date and time, got {created!r}") from None
        inputs = _field(data, "inputs", dict, where, {})
        if not all(isinstance(k, str) and k and isinstance(v, str) and _is_digest(v) for k, v in inputs.items()):
            raise RecordError(f"{where}: field 'inputs' must map file names to sha256 hex digests")
        status = _field(data, "status", str, where, "")
        if status and status not in STATUSES:
            raise RecordError(
                f"{where}: field 'status' must be one of {', '.join(map(repr, STATUSES))}, got {status!r}"
            )
        revisions = _field(data, "code_revisions", object, where, [])
        if not isinstance(revisions, list) or not all(isinstance(r, str) for r in revisions):
            raise RecordError(f"{where}: field 'code_revisions' must be a list of strings")
        runtimes = _field(data, "runtimes", object, where, [])
        if not isinstance(runtimes, list) or not all(
            isinstance(r, dict) and all(isinstance(k, str) and isinstance(v, str) for k, v in r.items())
            for r in runtimes
        ):
            raise RecordError(f"{where}: field 'runtimes' must be a list of objects mapping names to strings")
        config = dict(_field(data, "config", dict, where, {}))
        check_config(config, where)
        return cls(
            model=dict(model),
            planner=_nonempty(data, "planner", where),
            strategy=_nonempty(data, "strategy", where),
            prompt_version=_field(data, "prompt_version", str, where),
            dataset_hash=dataset,
            code_revision=_field(data, "code_revision", str, where, ""),
            config=config,
            schema=schema,
            created=created,
            inputs=dict(inputs),
            status=status,
            code_revisions=tuple(revisions),
            runtimes=tuple(dict(r) for r in runtimes),
        )


def _is_digest(text: str) -> bool:
    return len(text) == 64 and all(c in "0123456789abcdef" for c in text)


def _nonempty(data: Mapping[str, Any], name: str, where: str) -> str:
    value: str = _field(data, name, str, where)
    if not value:
        raise RecordError(f"{where}: field '{name}' must not be empty")
    return value


def _is_int(value: object) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def _is_scalar(value: object) -> bool:
    return isinstance(value, str | int | float | bool)


@functools.cache
def _planner_checks() -> dict[str, tuple[str, Any]]:
    """`config.NAME` -> (what it must be, a test), for every `SayCanConfig` field, from its type (or, when
    the annotation cannot be resolved, its default's type): a field added to the planner later is
    validated without an edit here."""
    import typing

    from talkdem.planner.saycan import SayCanConfig

    try:
        hints = typing.get_type_hints(SayCanConfig)
    except (NameError, TypeError):  # an annotation naming a type imported only for type checking
        hints = {}
    checks: dict[str, tuple[str, Any]] = {}
    for spec in dataclasses.fields(SayCanConfig):
        name = spec.name
        kind = hints.get(name, type(spec.default) if spec.default is not dataclasses.MISSING else None)
        if typing.get_origin(kind) is typing.Literal:
            allowed = typing.get_args(kind)
            checks[name] = (f"one of {', '.join(map(repr, allowed))}", lambda v, a=allowed: v in a)
        elif kind is bool:
            checks[name] = ("true or false", lambda v: isinstance(v, bool))
        elif kind is int:
            # A step limit of 0 plans nothing; every other count may be 0 (`log_top` 0: off).
            if name == "max_steps":
                checks[name] = ("a positive integer", lambda v: _is_int(v) and v >= 1)
            else:
                checks[name] = ("a non-negative integer", lambda v: _is_int(v) and v >= 0)
        elif kind is float:
            checks[name] = ("a finite number", lambda v: (_is_int(v) or isinstance(v, float)) and math.isfinite(v))
        elif kind is str:
            checks[name] = ("a string", lambda v: isinstance(v, str))
    return checks


def _is_shard(value: object) -> bool:
    if not isinstance(value, str):
        return False
    parts = value.split("/")
    return len(parts) == 2 and all(p.isdigit() for p in parts) and 1 <= int(parts[0]) <= int(parts[1])


_CONFIG_CHECKS: dict[str, tuple[str, Any]] = {
    "planned_episodes": ("a non-negative integer", lambda v: _is_int(v) and v >= 0),
    "limit": ("a positive integer or null", lambda v: v is None or (_is_int(v) and v >= 1)),
    "tasks": ("a positive integer", lambda v: _is_int(v) and v >= 1),
    "threads": ("a positive integer", lambda v: _is_int(v) and v >= 1),
    "conditions": ("a list of strings", lambda v: isinstance(v, list) and all(isinstance(c, str) for c in v)),
    "shard": ("I/N with 1 <= I <= N", _is_shard),
    "merged_from": ("a list of strings", lambda v: isinstance(v, list) and all(isinstance(c, str) for c in v)),
    "code_revisions": ("a list of strings", lambda v: isinstance(v, list) and all(isinstance(c, str) for c in v)),
    "served": ("an object", lambda v: isinstance(v, dict)),
    "plans": ("a string", lambda v: isinstance(v, str)),
    "clarify_generator": ("a string", lambda v: isinstance(v, str)),
    "plans_sha256": ("a sha256 hex digest", lambda v: isinstance(v, str) and _is_digest(v)),
    "strategy_args": (
        "map names to strings, numbers, true/false or lists of them",
        lambda v: (
            isinstance(v, dict)
            and all(
                isinstance(k, str) and (_is_scalar(x) or (isinstance(x, list) and all(_is_scalar(y) for y in x)))
                for k, x in v.items()
            )
        ),
    ),
    "backend_args": (
        "map names to strings, numbers or true/false",
        lambda v: isinstance(v, dict) and all(isinstance(k, str) and _is_scalar(x) for k, x in v.items()),
    ),
}


def check_config(config: Mapping[str, Any], where: str) -> None:
    """Every known `config` field of a header has its type and range (unknown fields pass: a newer
    version's, which this one does not read)."""
    for name, (expected, test) in {**_planner_checks(), **_CONFIG_CHECKS}.items():
        if name in config and not test(config[name]):
            phrase = expected if expected.startswith("map ") else f"be {expected}"
            raise RecordError(f"{where}: field 'config.{name}' must {phrase}, got {config[name]!r}")


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

    def with_dialogue(self, dialogue: Sequence[Exchange]) -> EpisodeRecord:
        """This record with a clarification episode's questions and answers in `trace.dialogue` (an empty list:
        asked nothing). The plan keeps the actions alone, so replaying it (`verify-run`, `score`) executes what
        was executed."""
        return dataclasses.replace(self, trace={**self.trace, "dialogue": [x.to_json() for x in dialogue]})

    def to_line(self) -> str:
        return json.dumps(self.to_json(), ensure_ascii=False, sort_keys=False)

    @classmethod
    def from_json(cls, data: object, where: str = "episode record") -> EpisodeRecord:
        """A validated record: field types, a plan of skill strings, an id that agrees with the task, pattern
        and level stored beside it, and the nested fields commands read (the trace's steps, goal report,
        hazards and dialogue, the hazard summary, goal counts, notes, timings: `talkdem.runs.record_fields`),
        so a hand-edited record is refused with one error naming `where` and the field, never scored."""
        if not isinstance(data, dict):
            raise RecordError(f"{where}: expected a JSON object, got {type(data).__name__}")
        episode_id = _field(data, "episode_id", str, where)
        where = f"{where} ({episode_id})"
        for name in ("hazards", "goal_conditions", "trace", "notes", "timing"):
            _field(data, name, list if name == "hazards" else dict, where, None)
        try:  # what every command reads inside them, checked once here (see `talkdem.runs.record_fields`)
            check_nested_fields(data)
        except FieldProblem as exc:
            raise RecordError(f"{where}: {exc}") from None
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
