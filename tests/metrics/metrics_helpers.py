"""Real tasks, real plans and small run directories for the metric, report and evaluate tests."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

from talkdem.metrics import split_instruction_id
from talkdem.runs import EpisodeRecord, EpisodeWriter, RunHeader, write_header
from talkdem.schema import CLEAN
from talkdem.sim import run_plan
from talkdem.tasks import get_task

BOOK = "trial_T20190908_111915_948834"  # pick_and_place_simple: a book on a desk
LAMP = "trial_T20190909_042617_850108"  # look_at_obj_in_light: a box under a desk lamp
HEAT = "trial_T20190909_152050_792044"  # pick_heat_then_place_in_recep: a potato, counter top
COOL = "trial_T20190909_080537_886002"  # pick_cool_then_place_in_recep: a bowl, counter top
CLEAN_TASK = "trial_T20190907_074106_050405"  # pick_clean_then_place_in_recep: a soap bar


def clean_id(task_id: str) -> str:
    return f"{task_id}:{CLEAN}:0"


def pattern_id(task_id: str, pattern: str, level: int) -> str:
    return f"{task_id}:{pattern}:{level}"


def reference(task_id: str) -> list[str]:
    return list(get_task(task_id).reference_plan)


def failing(task_id: str) -> list[str]:
    """Picks the target up and stops: fails every task here (a subgoal omission)."""
    return [*reference(task_id)[:2], "done"]


def write_run(
    run_dir: Path,
    plans: Mapping[str, Sequence[str]],
    *,
    model: str = "tiny-model",
    strategy: str = "vanilla",
    planner: str = "saycan",
) -> Path:
    """A run directory whose episodes are the given plans executed on their real tasks (as if `planner` wrote
    them; `external` marks plans from elsewhere)."""
    write_header(
        run_dir,
        RunHeader(
            model={"backend": "test", "name": model, "revision": "r0"},
            planner=planner,
            strategy=strategy,
            prompt_version="test",
            dataset_hash="0" * 64,  # a sha256 digest, as headers are validated on read
            code_revision="test",
        ),
    )
    with EpisodeWriter(run_dir) as writer:
        for instruction_id, plan in plans.items():
            task_id, condition = split_instruction_id(instruction_id)
            trace = run_plan(get_task(task_id), plan)
            summary = trace.summary()
            writer.write(
                EpisodeRecord(
                    episode_id=instruction_id,
                    task_id=task_id,
                    pattern=condition.pattern,
                    level=condition.level,
                    instruction="",
                    plan=tuple(plan),
                    success=trace.success,
                    hazards=tuple(summary["hazards"]),
                    goal_conditions=summary["goal_conditions"],
                    trace={},
                )
            )
    return run_dir
