"""Plans written by any other system, executed and recorded into a run directory exactly like our planner's
episodes (`talkdem score`); `talkdem report` scores the run like any other. To score plans in memory without a
run directory, `talkdem.metrics.score_plans` is the one function."""

from __future__ import annotations

import hashlib
from collections.abc import Mapping
from pathlib import Path

from talkdem.instructions import Instruction, load_instructions
from talkdem.plans import Plan, check_plan
from talkdem.runs.episode import play_plan
from talkdem.runs.records import RunHeader
from talkdem.runs.store import (
    HEADER_FILE,
    EpisodeWriter,
    finish_status,
    open_run,
    read_episodes,
    read_header,
    run_lock,
    set_status,
)
from talkdem.schema import canonical_instruction_id
from talkdem.serialization import parse_json

__all__ = ["EXTERNAL_RESUME_KEYS", "plans_digest", "read_plan_file", "record_plan_file", "record_plans"]

# A scored run is resumed or extended by the same system on the same dataset and input files (the tasks the
# plans execute on, the instructions). Which plans it holds is checked per episode instead of by one digest
# (an episode already in the run must come again with the same plan), so a second plan file can add
# episodes; the header's `plans_sha256` then covers every plan in the run.
EXTERNAL_RESUME_KEYS = ("model", "planner", "strategy", "dataset_hash", "inputs")


def read_plan_file(path: Path) -> dict[str, Plan]:
    """`{"episode_id": ..., "plan": [...]}` per line (`id` is accepted for `episode_id`); errors name the line.

    Ids follow the metric's rule (`talkdem.schema.canonical_instruction_id`): `<task>:clean` is the clean
    instruction's short form, stored under its long form `<task>:clean:0`."""
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise FileNotFoundError(f"{path}: plan file not found") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise ValueError(f"{path}: cannot read the plan file ({exc})") from None
    known = {i.id for i in load_instructions()}
    plans: dict[str, Plan] = {}
    for number, line in enumerate(text.splitlines(), start=1):
        if not line.strip():
            continue
        where = f"{path}, line {number}"
        row = parse_json(line, where)
        episode_id = row.get("episode_id", row.get("id")) if isinstance(row, dict) else None
        if not isinstance(episode_id, str):
            raise ValueError(f"{where}: expected an object with a string 'episode_id'")
        plan = check_plan(row.get("plan"), f"{where} ({episode_id})")
        try:
            canonical = canonical_instruction_id(episode_id)
        except ValueError as exc:
            raise ValueError(f"{where}: {exc}") from None
        if canonical not in known:
            raise ValueError(f"{where}: unknown episode id '{episode_id}'")
        episode_id = canonical
        if episode_id in plans:
            raise ValueError(f"{where}: duplicate episode id '{episode_id}'")
        plans[episode_id] = plan
    if not plans:
        raise ValueError(f"{path}: no plans")
    return plans


def plans_digest(plans: Mapping[str, Plan]) -> str:
    """sha256 over the plans in id order: names a set of external plans without naming a file path."""
    digest = hashlib.sha256()
    for episode_id in sorted(plans):
        digest.update(episode_id.encode() + b"\0" + "\x1f".join(plans[episode_id]).encode() + b"\0")
    return digest.hexdigest()


def record_plans(
    plans: Mapping[str, Plan],
    run_dir: Path,
    system_name: str,
    strategy: str = "external",
    source: str = "",
    *,
    new_revision_ok: bool = False,
    model: str = "",
    version: str = "",
) -> int:
    """Execute every plan into `run_dir` (planner `external`); returns the number of episodes in the run.

    An existing run of the same system is resumed (a run killed part-way) or extended (a second plan file
    with more episodes): episodes already there are kept, and must come with the plan they were scored
    with, new ones are executed and appended. `source` names where the plans came from (a file name, never
    a machine path: the header is published). A run started on another code revision is resumed only with
    `new_revision_ok` (both revisions are recorded). `model` and `version` name what the
    system ran on and which version of it wrote the plans (recorded; a new version is another run)."""
    from talkdem.runs.spec import input_hashes

    by_id: dict[str, Instruction] = {i.id: i for i in load_instructions()}
    unknown = [episode_id for episode_id in plans if episode_id not in by_id]
    if unknown:
        raise ValueError(f"unknown episode ids: {', '.join(unknown[:5])}")
    with run_lock(run_dir):
        stored: dict[str, Plan] = {}
        sources = [source] if source else []
        if (run_dir / HEADER_FILE).exists():
            stored = {episode.episode_id: episode.plan for episode in read_episodes(run_dir, repair=True)}
            earlier = read_header(run_dir).config.get("plans", "")
            sources = [*str(earlier).split(", "), *sources] if earlier else sources
        changed = [i for i, plan in plans.items() if i in stored and tuple(stored[i]) != tuple(plan)]
        if changed:
            raise ValueError(
                f"{run_dir}: {len(changed)} episode(s) already in the run with another plan (its plans_sha256 "
                f"covers each plan once; score changed plans into a new --out): {', '.join(changed[:3])}"
            )
        everything = {**stored, **plans}
        header = RunHeader.new(
            model={"backend": "external", "name": system_name, "revision": version},
            planner="external",
            strategy=strategy,
            prompt_version="",
            config={
                "agent": {"name": system_name, "model": model, "strategy": strategy, "version": version},
                "plans": ", ".join(dict.fromkeys(sources)),
                "plans_sha256": plans_digest(everything),
                "planned_episodes": len(everything),
            },
            inputs=input_hashes(planner=False),
        )
        opened = open_run(run_dir, header, EXTERNAL_RESUME_KEYS, new_revision_ok=new_revision_ok)
        done = {episode.episode_id for episode in opened}
        try:
            with EpisodeWriter(run_dir) as writer:
                for episode_id, plan in plans.items():
                    if episode_id in done:
                        continue
                    record, _ = play_plan(by_id[episode_id], plan)
                    writer.write(record)
        except BaseException:
            set_status(run_dir, "incomplete")
            raise
        finish_status(run_dir, list(everything))
    return len(everything)


def record_plan_file(
    path: Path,
    run_dir: Path,
    system_name: str,
    strategy: str = "external",
    *,
    new_revision_ok: bool = False,
    model: str = "",
    version: str = "",
) -> int:
    """Execute every plan of `path` into `run_dir` (planner `external`); returns the number of episodes."""
    return record_plans(
        read_plan_file(path),
        run_dir,
        system_name,
        strategy,
        source=path.name,
        new_revision_ok=new_revision_ok,
        model=model,
        version=version,
    )
