"""The one way from a plan to an episode record: step it through the simulator seam, then `from_trace`.

Our planners step the seam live; `talkdem score`, the oracle, the `evaluate` metric and `talkdem verify-run`
execute stored plans through `play_plan`. All of them end in `EpisodeRecord.from_trace`, so an outcome cannot
depend on which door a plan came in by.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from talkdem.instructions import Instruction
from talkdem.runs.records import EpisodeRecord
from talkdem.sim.seam import DEFAULT_MAX_STEPS, SimulatorBackend, execute_plan, load_simulator
from talkdem.sim.trace import EpisodeTrace

__all__ = ["out_of_vocabulary_steps", "play_plan"]


def play_plan(
    instruction: Instruction,
    plan: Sequence[str],
    *,
    max_steps: int = DEFAULT_MAX_STEPS,
    simulator: SimulatorBackend | None = None,
    notes: dict[str, str] | None = None,
) -> tuple[EpisodeRecord, EpisodeTrace]:
    """Execute `plan` for `instruction`'s task (steps after `done` or past the limit are not run) and
    return its record (the plan as given) and the live trace."""
    from talkdem.tasks import get_task

    backend = simulator if simulator is not None else load_simulator()
    trace = execute_plan(backend, get_task(instruction.task_id), plan, max_steps=max_steps)
    return EpisodeRecord.from_trace(instruction, tuple(plan), trace, notes=notes), trace


def out_of_vocabulary_steps(run_dir: Path) -> tuple[int, int]:
    """(steps naming no skill, episodes with at least one) over a run directory's stored traces."""
    from talkdem.runs.store import read_episodes

    steps = episodes = 0
    for record in read_episodes(run_dir):
        count = sum(1 for step in record.trace.get("steps", ()) if step.get("parsed") is None)
        steps += count
        episodes += count > 0
    return steps, episodes
