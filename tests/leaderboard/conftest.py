"""Real run directories of different coverage for the leaderboard tests, made as a user makes them:
external plans through `talkdem score`, the oracle through `write_oracle_run`, planner-written runs through
`metrics_helpers.write_run` (real plans executed on real tasks; the planner itself is not run here).

    "planner A", "planner_A"  external, 4 tasks x 16 conditions, identical plans (a tie; names that differ
                              only in punctuation)
    "planner-B"               external, the same 64 episodes, worse at levels 2-3
    SmolLM2 vanilla / care    saycan (model given as a path), 1 task x 16 conditions
    oracle                    reference plans, 1 task x 16 conditions
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).parent.parent / "metrics"))
sys.path.insert(0, str(Path(__file__).parent))

from metrics_helpers import BOOK, COOL, HEAT, LAMP, failing, reference, write_run

from talkdem.cli import main
from talkdem.instructions import load_instructions

TASKS = (BOOK, LAMP, HEAT, COOL)
MODEL_PATH = "/home/someone/models/SmolLM2-135M-Instruct.Q4_1.gguf"


def _plans(tasks: tuple[str, ...], fails: set[tuple[str, int]]) -> dict[str, list[str]]:
    """Reference plans, failing ones for (task, level) in `fails`."""
    return {
        i.id: failing(i.task_id) if (i.task_id, i.condition.level) in fails else reference(i.task_id)
        for i in load_instructions()
        if i.task_id in tasks
    }


def _score(root: Path, name: str, plans: dict[str, list[str]]) -> Path:
    plan_file = root / f"{name.replace(' ', '-')}.jsonl"
    plan_file.write_text("".join(json.dumps({"episode_id": k, "plan": v}) + "\n" for k, v in plans.items()))
    out = root / f"run-{len(list(root.glob('run-*')))}"
    assert main(["score", str(plan_file), "--name", name, "--out", str(out)]) == 0
    return out


@pytest.fixture(scope="session")
def board_runs(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    from talkdem.runs.oracle import write_oracle_run

    root = tmp_path_factory.mktemp("board-runs")
    a_fails = {(LAMP, 3)}
    b_fails = {(LAMP, 2), (LAMP, 3), (HEAT, 3), (COOL, 3)}
    runs = {
        "planner A": _score(root, "planner A", _plans(TASKS, a_fails)),
        "planner_A": _score(root, "planner_A", _plans(TASKS, a_fails)),
        "planner-B": _score(root, "planner-B", _plans(TASKS, b_fails)),
    }
    one = {i.id: failing(i.task_id) for i in load_instructions() if i.task_id == BOOK}
    runs["smol vanilla"] = write_run(root / "smol-vanilla", one, model=MODEL_PATH, strategy="vanilla")
    care = {k: reference(BOOK) if ":clean" in k or k.endswith(":1") else v for k, v in one.items()}
    runs["smol care"] = write_run(root / "smol-care", care, model=MODEL_PATH, strategy="care")
    oracle = root / "oracle"
    write_oracle_run([i for i in load_instructions() if i.task_id == BOOK], oracle)
    runs["oracle"] = oracle
    return runs


@pytest.fixture(scope="session")
def board(board_runs: dict[str, Path], tmp_path_factory: pytest.TempPathFactory) -> Path:
    """`talkdem leaderboard --out DIR` over every run (bootstrap on, so intervals show)."""
    out = tmp_path_factory.mktemp("board") / "space"
    assert main(["leaderboard", *map(str, board_runs.values()), "--out", str(out), "--bootstrap", "200"]) == 0
    return out
