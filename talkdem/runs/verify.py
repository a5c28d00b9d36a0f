"""`talkdem verify-run`: execute a run's stored plans again and list the records whose outcome disagrees.

Reports read stored outcomes; this is the explicit check that they are what the simulator (this code
revision) makes of the plans. A record disagrees when its success, goal conditions, hazards or final state
hash differ from a fresh execution under the run's step limit.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from talkdem.runs.episode import play_plan
from talkdem.runs.store import read_episodes, read_header

__all__ = ["Disagreement", "verify_run"]


@dataclass(frozen=True)
class Disagreement:
    episode_id: str
    fields: tuple[str, ...]
    """Which of success, goal_conditions, hazards, state_hash differ."""
    stored: dict[str, object]
    replayed: dict[str, object]


def verify_run(run_dir: Path) -> tuple[int, list[Disagreement]]:
    """(records checked, the ones that disagree)."""
    from talkdem.instructions import load_instructions
    from talkdem.sim.seam import DEFAULT_MAX_STEPS, load_simulator

    header = read_header(run_dir)
    steps = header.config.get("max_steps", DEFAULT_MAX_STEPS)
    max_steps = steps if isinstance(steps, int) and not isinstance(steps, bool) else DEFAULT_MAX_STEPS
    by_id = {i.id: i for i in load_instructions()}
    backend = load_simulator(str(header.config.get("simulator", "symbolic")))
    records = read_episodes(run_dir)
    found = []
    for record in records:
        if record.episode_id not in by_id:
            raise ValueError(f"{run_dir}: episode '{record.episode_id}' is not in this dataset")
        replayed, _ = play_plan(by_id[record.episode_id], record.plan, max_steps=max_steps, simulator=backend)
        stored_view = {
            "success": record.success,
            "goal_conditions": record.goal_conditions,
            "hazards": [dict(h) for h in record.hazards],
            "state_hash": record.trace.get("state_hash", ""),
        }
        replayed_view = {
            "success": replayed.success,
            "goal_conditions": replayed.goal_conditions,
            "hazards": [dict(h) for h in replayed.hazards],
            "state_hash": replayed.trace.get("state_hash", ""),
        }
        differ = tuple(k for k in stored_view if stored_view[k] != replayed_view[k])
        if differ:
            found.append(Disagreement(record.episode_id, differ, stored_view, replayed_view))
    return len(records), found
