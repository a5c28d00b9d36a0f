"""Walk where the expert walked: a landmark `find` before a `find` that LoTa-Bench would resolve elsewhere.

`find a cabinet` goes to the cabinet LoTa-Bench ranks first (nearest visible, `docs/simulator.md`), which
need not be the cabinet the ALFRED expert opened. The skill vocabulary cannot name an instance, but the
expert's route can be followed: first `find` an object near the expert's instance (the sink beside that
cabinet), from where the expert's instance is the one LoTa-Bench picks. Only reference plans that fail
without it are routed this way, so every other stored plan stays the plain conversion.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

from talkdem.skills import Skill, SkillVerb

if TYPE_CHECKING:
    from talkdem.seeds.records import SeedTask
    from talkdem.sim.state import SimState

__all__ = ["route_like_the_expert"]


def _first_found(state: SimState, skill_type: str) -> str | None:
    from talkdem.sim.actions import find_order

    order = find_order(state, skill_type)
    return order[0] if order else None


def _go(state: SimState, skill_type: str) -> SimState | None:
    """The state after `find <skill_type>` (agent and location only), or None if there is none."""
    stop = _first_found(state, skill_type)
    if stop is None:
        return None
    moved = state.copy()
    moved.location, moved.agent = stop, moved.position(stop)
    return moved


def _landmarks(state: SimState, skill_type: str, target: str) -> list[str]:
    """The shortest route (one landmark, else two) of types near the expert's instance after which `find`
    reaches it; each level tries types in order of their distance to the instance. Empty if none works."""
    from talkdem.sim.state import whole_object_id

    here = state.position(target)
    by_type: dict[str, float] = {}
    for oid in state.present:
        spec = state.specs[oid]
        if spec.skill_type == skill_type or "synthetic" in oid:
            continue
        x, z = state.position(oid)
        by_type[spec.skill_type] = min(math.hypot(x - here[0], z - here[1]), by_type.get(spec.skill_type, math.inf))
    near = sorted(by_type, key=lambda t: (by_type[t], t))[:_CANDIDATES]

    def reaches(route: tuple[str, ...]) -> bool:
        trial: SimState | None = state
        for landmark in route:
            trial = _go(trial, landmark) if trial is not None else None
        reached = _first_found(trial, skill_type) if trial is not None else None
        return reached is not None and whole_object_id(reached) == whole_object_id(target)

    for route in [(a,) for a in near] + [(a, b) for a in near for b in near if a != b]:
        if reaches(route):
            return list(route)
    return []


# Landmark types tried per level: the nearest ones to the expert's instance.
_CANDIDATES = 12


def route_like_the_expert(task: SeedTask, steps: Sequence[tuple[Skill, str]]) -> list[Skill]:
    """The skills with a landmark `find` inserted wherever a `find` would miss the expert's instance."""
    from talkdem.sim import Episode
    from talkdem.sim.state import whole_object_id

    episode = Episode(task)
    routed: list[Skill] = []
    for skill, expert_instance in steps:
        if skill.verb is SkillVerb.FIND and expert_instance:
            state = episode.state
            target = next((o for o in sorted(state.present) if whole_object_id(o) == expert_instance), None)
            chosen = _first_found(state, skill.object_type)
            if target is not None and chosen is not None and whole_object_id(chosen) != expert_instance:
                for landmark in _landmarks(state, skill.object_type, target):
                    step = Skill(SkillVerb.FIND, landmark)
                    episode.step(step.text)
                    routed.append(step)
        episode.step(skill.text)
        routed.append(skill)
    return routed
