"""Write any agent's episodes as a standard run directory (what report, leaderboard and evaluate read).

The header names the agent (name, version, and, if the author gives them, its model and strategy); each
episode becomes one `EpisodeRecord.from_trace`, the constructor every writer uses. Plans come from the
agent, so the planner is `external`, as for `talkdem score`. A killed recording resumes: episodes already on
disk are kept, and `recorded` says which ids to skip.

The header's `status` follows the rule every run writer uses (`talkdem.runs.store`): `running` while the
recorder is open; when it closes normally, `complete` if every planned episode is on disk (no `planned`: the
recorded episodes are the run), else `incomplete`; `incomplete` when the `with` block ends in an exception.
"""

from __future__ import annotations

from collections.abc import Sequence
from contextlib import ExitStack
from pathlib import Path
from types import TracebackType
from typing import Any

from talkdem.clarify import Exchange
from talkdem.instructions import Instruction
from talkdem.runs.records import EpisodeRecord, RunHeader
from talkdem.runs.store import EpisodeWriter, finish_status, open_run, run_lock, set_status
from talkdem.sim.trace import EpisodeTrace

__all__ = ["AGENT_RESUME_KEYS", "EpisodeRecorder"]

# A recording resumes only for the same agent and version on the same data and step limit.
AGENT_RESUME_KEYS = ("model", "planner", "strategy", "dataset_hash", "config.max_steps", "config.agent")


class EpisodeRecorder:
    """`with EpisodeRecorder(run_dir, "my-agent", "1.0") as rec: rec.record(instruction, plan, trace)`."""

    def __init__(
        self,
        run_dir: Path,
        agent: str,
        version: str,
        *,
        model: str = "",
        strategy: str = "external",
        max_steps: int | None = None,
        planned: Sequence[Instruction] = (),
        config: dict[str, Any] | None = None,
        clarify: str = "none",
    ) -> None:
        from talkdem.sim.seam import DEFAULT_MAX_STEPS

        if not agent.strip():
            raise ValueError("an agent recording needs the agent's name")
        self.run_dir = run_dir
        self.planned = tuple(instruction.id for instruction in planned)
        self.header = RunHeader.new(
            model={"backend": "agent", "name": agent, "revision": version},
            planner="external",
            strategy=strategy,
            prompt_version="",
            config={
                "agent": {"name": agent, "version": version, "model": model},
                "max_steps": DEFAULT_MAX_STEPS if max_steps is None else max_steps,
                **(config or {}),
                **({"clarify": clarify} if clarify != "none" else {}),
                **({"planned_episodes": len(planned)} if planned else {}),
            },
        )
        self._hold = ExitStack()  # one writer at a time, as for every run directory
        try:
            self._hold.enter_context(run_lock(run_dir))
            self.recorded = {e.episode_id for e in open_run(run_dir, self.header, AGENT_RESUME_KEYS)}
            # Unwound in reverse: the writer closes, then the status is set, then the lock is let go.
            self._hold.push(self._set_status)
            self._writer = self._hold.enter_context(EpisodeWriter(run_dir))
        except BaseException as error:
            self._hold.__exit__(type(error), error, error.__traceback__)
            raise

    def _set_status(
        self, kind: type[BaseException] | None, value: BaseException | None, traceback: TracebackType | None
    ) -> None:
        """The run header's final status, as `talkdem run` and `talkdem score` set it."""
        if kind is not None:
            set_status(self.run_dir, "incomplete")
        else:
            finish_status(self.run_dir, self.planned)  # nothing planned: complete, what was recorded is the run

    def record(
        self,
        instruction: Instruction,
        plan: Sequence[str],
        trace: EpisodeTrace,
        notes: dict[str, str] | None = None,
        dialogue: Sequence[Exchange] | None = None,
    ) -> EpisodeRecord:
        """Append one finished episode (an id already recorded is refused: one record per episode).
        `plan`: the actions alone; `dialogue`: the questions asked on the way (the env's `info["dialogue"]`),
        stored as `talkdem run --clarify` stores them, so the report's clarification metrics read them."""
        if instruction.id in self.recorded:
            raise ValueError(f"{self.run_dir}: episode '{instruction.id}' is already recorded")
        if trace.task_id != instruction.task_id:
            raise ValueError(f"episode '{instruction.id}': the trace is of task '{trace.task_id}'")
        record = EpisodeRecord.from_trace(instruction, tuple(plan), trace, notes=notes)
        if dialogue is not None:
            record = record.with_dialogue(dialogue)
        self._writer.write(record)
        self.recorded.add(instruction.id)
        return record

    def close(self) -> None:
        """Finish the recording: the header's status becomes `complete` or `incomplete` (see the module)."""
        self._hold.close()

    def __enter__(self) -> EpisodeRecorder:
        return self

    def __exit__(
        self, kind: type[BaseException] | None, value: BaseException | None, traceback: TracebackType | None
    ) -> None:
        self._hold.__exit__(kind, value, traceback)
