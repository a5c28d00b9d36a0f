"""The oracle row: the reference plans of the sampled episodes, executed and stored like any run."""

from __future__ import annotations

import json
import tempfile
from collections.abc import Sequence
from pathlib import Path

from talkdem.instructions import Instruction
from talkdem.runs.external import score_plan_file
from talkdem.tasks import get_task

__all__ = ["write_oracle_run"]


def write_oracle_run(episodes: Sequence[Instruction], run_dir: Path) -> int:
    """A run directory (planner `external`, name `oracle`) whose plans are the tasks' reference plans."""
    with tempfile.TemporaryDirectory() as scratch:
        plan_file = Path(scratch) / "oracle.jsonl"
        rows = [{"episode_id": e.id, "plan": list(get_task(e.task_id).reference_plan)} for e in episodes]
        plan_file.write_text("".join(json.dumps(row) + "\n" for row in rows))
        if run_dir.exists():
            for old in run_dir.iterdir():
                old.unlink()
        return score_plan_file(plan_file, run_dir, "oracle", strategy="reference plans")
