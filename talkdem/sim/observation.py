"""What an agent is told after each step: the simulator's answer in words, as LoTa-Bench's skill layer gives it.

LoTa-Bench's `llm_skill_interact` returns an empty message on success and a failure message otherwise
(`Cannot find Mug`, `Robot is currently holding Apple`, `instruction not supported`); the step record keeps
exactly that message. Here it is framed as one sentence an agent can read: which skill ran and whether it
succeeded, so a transcript of observations reads on its own.
"""

from __future__ import annotations

from talkdem.sim.trace import StepRecord

__all__ = ["observation_of"]


def observation_of(record: StepRecord) -> str:
    """One line: `find an apple: done.` / `pick up the mug: failed (Cannot find Mug to pick up).`"""
    skill = record.parsed or record.skill.strip() or "(empty action)"
    if record.parsed == "done":
        return "done: the episode is over."
    if record.ok:
        return f"{skill}: succeeded."
    message = record.message.rstrip(".") or "failed"
    return f"{skill}: failed ({message})."
