"""The run directory: what one planner run produced, in a stable schema that scoring and leaderboards read.

    RUN_DIR/header.json      RunHeader: model identity, planner, strategy, prompt version, dataset hash,
                             code revision, configuration
    RUN_DIR/episodes.jsonl   one EpisodeRecord per line, appended as episodes finish (resumable)

Plans from any other system become a run directory through `talkdem score` (planner `external`), so the
benchmark never requires our planner.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from typing import Any

__all__ = ["RUN_SCHEMA", "EpisodeRecord", "RunHeader"]

RUN_SCHEMA = "talkdem-run/1"


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
    """Planner settings (step limit, scoring, feedback policy), conditions, sample size, seed."""
    schema: str = RUN_SCHEMA
    created: str = ""

    def to_json(self) -> dict[str, Any]:
        return {
            "schema": self.schema,
            "model": self.model,
            "planner": self.planner,
            "strategy": self.strategy,
            "prompt_version": self.prompt_version,
            "dataset_hash": self.dataset_hash,
            "code_revision": self.code_revision,
            "config": self.config,
            "created": self.created,
        }

    @classmethod
    def from_json(cls, data: dict[str, Any]) -> RunHeader:
        missing = [k for k in ("model", "planner", "strategy", "prompt_version", "dataset_hash") if k not in data]
        if missing:
            raise ValueError(f"run header lacks {', '.join(missing)}")
        if data.get("schema", RUN_SCHEMA) != RUN_SCHEMA:
            raise ValueError(f"run header schema {data.get('schema')!r} is not {RUN_SCHEMA!r}")
        return cls(
            model=dict(data["model"]),
            planner=data["planner"],
            strategy=data["strategy"],
            prompt_version=data["prompt_version"],
            dataset_hash=data["dataset_hash"],
            code_revision=data.get("code_revision", ""),
            config=dict(data.get("config", {})),
            schema=data.get("schema", RUN_SCHEMA),
            created=data.get("created", ""),
        )


@dataclass(frozen=True)
class EpisodeRecord:
    """One episode: the instruction, the plan, and what the simulator made of it."""

    episode_id: str
    """The instruction id, `<task_id>:clean` or `<task_id>:<pattern>:<level>`."""
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

    def to_json(self) -> dict[str, Any]:
        return {
            "episode_id": self.episode_id,
            "task_id": self.task_id,
            "pattern": self.pattern,
            "level": self.level,
            "instruction": self.instruction,
            "instruction_shown": self.instruction_shown,
            "plan": list(self.plan),
            "success": self.success,
            "hazards": list(self.hazards),
            "goal_conditions": self.goal_conditions,
            "notes": self.notes,
            "timing": self.timing,
            "trace": self.trace,
        }

    def to_line(self) -> str:
        return json.dumps(self.to_json(), ensure_ascii=False, sort_keys=False)

    @classmethod
    def from_json(cls, data: dict[str, Any]) -> EpisodeRecord:
        return cls(
            episode_id=data["episode_id"],
            task_id=data["task_id"],
            pattern=data["pattern"],
            level=int(data["level"]),
            instruction=data["instruction"],
            plan=tuple(data["plan"]),
            success=bool(data["success"]),
            hazards=tuple(data.get("hazards", ())),
            goal_conditions=dict(data.get("goal_conditions", {})),
            trace=dict(data.get("trace", {})),
            instruction_shown=data.get("instruction_shown", ""),
            notes=dict(data.get("notes", {})),
            timing=dict(data.get("timing", {})),
        )
