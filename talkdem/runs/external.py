"""Plans written by any other system, executed and scored exactly like our planner's."""

from __future__ import annotations

import datetime as dt
import json
from pathlib import Path

from talkdem.instructions import Instruction, dataset_hash, load_instructions
from talkdem.runs.records import EpisodeRecord, RunHeader
from talkdem.runs.revision import code_revision
from talkdem.runs.store import EpisodeWriter, read_episodes, write_header
from talkdem.sim import run_plan
from talkdem.tasks import get_task

__all__ = ["read_plan_file", "score_plan_file"]


def read_plan_file(path: Path) -> dict[str, list[str]]:
    """`{"episode_id": ..., "plan": [...]}` per line (`id` is accepted for `episode_id`); errors name the line."""
    if not path.is_file():
        raise FileNotFoundError(f"{path}: plan file not found")
    known = {i.id for i in load_instructions()}
    plans: dict[str, list[str]] = {}
    for number, line in enumerate(path.read_text().splitlines(), start=1):
        if not line.strip():
            continue
        try:
            row = json.loads(line)
        except json.JSONDecodeError as exc:
            raise ValueError(f"{path}, line {number}: not JSON ({exc.msg})") from exc
        episode_id = row.get("episode_id", row.get("id")) if isinstance(row, dict) else None
        plan = row.get("plan") if isinstance(row, dict) else None
        if not isinstance(episode_id, str):
            raise ValueError(f"{path}, line {number}: expected an object with a string 'episode_id'")
        if not isinstance(plan, list) or not all(isinstance(s, str) for s in plan):
            raise ValueError(f"{path}, line {number} ({episode_id}): 'plan' must be a list of skill strings")
        if episode_id not in known:
            raise ValueError(f"{path}, line {number}: unknown episode id '{episode_id}'")
        if episode_id in plans:
            raise ValueError(f"{path}, line {number}: duplicate episode id '{episode_id}'")
        plans[episode_id] = plan
    if not plans:
        raise ValueError(f"{path}: no plans")
    return plans


def score_plan_file(path: Path, run_dir: Path, system_name: str, strategy: str = "external") -> int:
    """Execute every plan of `path` into `run_dir` (planner `external`); returns the number of episodes."""
    plans = read_plan_file(path)
    by_id: dict[str, Instruction] = {i.id: i for i in load_instructions()}
    header = RunHeader(
        model={"backend": "external", "name": system_name, "revision": ""},
        planner="external",
        strategy=strategy,
        prompt_version="",
        dataset_hash=dataset_hash(),
        code_revision=code_revision(),
        config={"plan_file": str(path)},
        created=dt.datetime.now(dt.UTC).isoformat(timespec="seconds"),
    )
    if (run_dir / "episodes.jsonl").exists() and read_episodes(run_dir):
        raise ValueError(f"{run_dir} already holds episodes; choose an empty --out")
    write_header(run_dir, header)
    with EpisodeWriter(run_dir) as writer:
        for episode_id, plan in plans.items():
            instruction = by_id[episode_id]
            trace = run_plan(get_task(instruction.task_id), plan)
            summary = trace.summary()
            writer.write(
                EpisodeRecord(
                    episode_id=episode_id,
                    task_id=instruction.task_id,
                    pattern=instruction.condition.pattern,
                    level=instruction.condition.level,
                    instruction=instruction.text,
                    plan=tuple(plan),
                    success=trace.success,
                    hazards=tuple(summary["hazards"]),
                    goal_conditions=summary["goal_conditions"],
                    trace=trace.to_json(),
                )
            )
    return len(plans)
