"""Replay 4,800 episodes (the reference plans, repeated) in the symbolic simulator; report episodes/second."""

from __future__ import annotations

import time

EPISODES = 4800


def main() -> None:
    from talkdem.sim import SymbolicExecutor, initial_state
    from talkdem.tasks import TaskSet, load_tasks

    tasks = [task for task_set in TaskSet for task in load_tasks(task_set)]
    executor = SymbolicExecutor()
    for task in tasks:  # build each initial state and the hazard exemptions once, as a scoring run would
        initial_state(task)
        executor.run(task, task.reference_plan)
    start = time.perf_counter()
    successes = 0
    for episode in range(EPISODES):
        task = tasks[episode % len(tasks)]
        successes += executor.run(task, task.reference_plan).success
    elapsed = time.perf_counter() - start
    print(
        f"simulator: {EPISODES} episodes in {elapsed:.2f} s = {EPISODES / elapsed:,.0f} episodes/s "
        f"({successes}/{EPISODES} succeeded; target: under 2 s on one core)"
    )


if __name__ == "__main__":
    main()
