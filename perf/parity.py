"""Replay every stored parity case on the symbolic backend: agreement (must be 1.000) and time."""

from __future__ import annotations

import time


def main() -> None:
    from talkdem.sim import SymbolicExecutor
    from talkdem.sim.parity import format_report, load_cases, parity_file, replay
    from talkdem.tasks import TaskSet, load_tasks

    tasks = {t.task_id: t for t in load_tasks(TaskSet.BENCHMARK)}
    cases = load_cases(parity_file())
    start = time.perf_counter()
    report = replay(cases, tasks, SymbolicExecutor())
    elapsed = time.perf_counter() - start
    print(format_report(report))
    print(f"parity: {report.cases} cases replayed in {elapsed:.2f} s")


if __name__ == "__main__":
    main()
