"""The oracle row: the reference plans of the sampled episodes, executed and stored like any run."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from talkdem.instructions import Instruction
from talkdem.runs.external import plans_digest, record_plans
from talkdem.runs.store import EPISODES_FILE, HEADER_FILE, PACKED_EPISODES_FILE, read_header, run_lock
from talkdem.tasks import get_task

__all__ = ["ORACLE_NAME", "ORACLE_STRATEGY", "write_oracle_run"]

ORACLE_NAME = "oracle"
ORACLE_STRATEGY = "reference plans"


def write_oracle_run(episodes: Sequence[Instruction], run_dir: Path) -> int:
    """A run directory (planner `external`, name `oracle`) whose plans are the tasks' reference plans.

    An oracle run of another sample, input files or code revision in `run_dir` is replaced (it is derived
    data, cheap to remake); any other run there is refused by `record_plans`, never deleted."""
    from talkdem.runs.revision import code_revision
    from talkdem.runs.spec import input_hashes

    plans = {e.id: get_task(e.task_id).reference_plan for e in episodes}
    if (run_dir / HEADER_FILE).is_file():
        with run_lock(run_dir):
            header = read_header(run_dir)
            is_ours = header.planner == "external" and header.model.get("name") == ORACLE_NAME
            stale = (
                header.config.get("plans_sha256") != plans_digest(plans)
                or header.code_revision != code_revision()
                or header.inputs != input_hashes(planner=False)
            )
            if is_ours and stale:
                for name in (EPISODES_FILE, PACKED_EPISODES_FILE, HEADER_FILE):
                    (run_dir / name).unlink(missing_ok=True)
    return record_plans(plans, run_dir, ORACLE_NAME, strategy=ORACLE_STRATEGY, source="reference plans")
