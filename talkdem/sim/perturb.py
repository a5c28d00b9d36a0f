"""Seeded perturbations of a task's reference plan: the cases the parity suite replays on every backend.

Each kind is a mistake a planner makes: steps in the wrong order, a step left out, the wrong object, the wrong
destination, a skill added or repeated, and (movable-receptacle tasks) the container put down before the object.
Everything is drawn from `random.Random(f"{task_id}:{kind}:{i}")`, so the cases depend only on the task record.
"""

from __future__ import annotations

import random
from collections.abc import Sequence
from dataclasses import dataclass
from enum import StrEnum

from talkdem.seeds.records import SeedTask
from talkdem.sim.initial_state import initial_state
from talkdem.sim.parser import parse_skill
from talkdem.skills import Skill, SkillVerb, skill_texts

__all__ = ["PERTURBATIONS_PER_KIND", "PerturbationKind", "PerturbedPlan", "perturb"]

PERTURBATIONS_PER_KIND = 2
"""Cases per kind and task (container-first has one: it is fully determined by the task)."""


class PerturbationKind(StrEnum):
    REORDER = "reorder"
    DROP = "drop"
    WRONG_OBJECT = "wrong_object"
    WRONG_DESTINATION = "wrong_destination"
    EXTRA = "extra"
    CONTAINER_FIRST = "container_first"


@dataclass(frozen=True)
class PerturbedPlan:
    """One case: its id (`<task>:<kind>:<i>`), its kind, and the plan."""

    case_id: str
    kind: PerturbationKind
    plan: tuple[str, ...]


def _body(plan: Sequence[str]) -> list[str]:
    """The plan without its final `done`."""
    return list(plan[:-1]) if plan and plan[-1] == "done" else list(plan)


def _reorder(rng: random.Random, body: list[str]) -> list[str] | None:
    if len(body) < 2:
        return None
    i = rng.randrange(len(body) - 1)
    body[i], body[i + 1] = body[i + 1], body[i]
    return body


def _drop(rng: random.Random, body: list[str]) -> list[str] | None:
    if len(body) < 2:
        return None
    del body[rng.randrange(len(body))]
    return body


def _swap_type(rng: random.Random, body: list[str], verbs: set[SkillVerb], pool: list[str]) -> list[str] | None:
    """Replace the object of one step whose verb is in `verbs` (and of the `find` before it) by another type."""
    slots = [i for i, s in enumerate(body) if (k := parse_skill(s)) is not None and k.verb in verbs]
    if not slots:
        return None
    i = rng.choice(slots)
    skill = parse_skill(body[i])
    assert skill is not None
    choices = [t for t in pool if t != skill.object_type and Skill(skill.verb, t).text in skill_texts()]
    if not choices:
        return None
    new_type = rng.choice(choices)
    body[i] = Skill(skill.verb, new_type).text
    if skill.verb is not SkillVerb.FIND and i > 0 and body[i - 1] == Skill(SkillVerb.FIND, skill.object_type).text:
        body[i - 1] = Skill(SkillVerb.FIND, new_type).text
    return body


def _wrong_destination(rng: random.Random, body: list[str], receptacles: list[str]) -> list[str] | None:
    """Send one `put down` elsewhere: replace the `find` that precedes it by a find of another receptacle type."""
    slots = []
    for i, s in enumerate(body):
        k = parse_skill(s)
        if k is None or k.verb is not SkillVerb.PUT_DOWN:
            continue
        finds = [j for j in range(i - 1, -1, -1) if body[j].startswith("find ")]
        if finds:
            slots.append(finds[0])
    if not slots:
        return None
    j = rng.choice(slots)
    found = parse_skill(body[j])
    assert found is not None
    choices = [t for t in receptacles if t != found.object_type]
    if not choices:
        return None
    body[j] = Skill(SkillVerb.FIND, rng.choice(choices)).text
    return body


def _extra(rng: random.Random, body: list[str], pool: list[Skill]) -> list[str] | None:
    """Repeat one step right after itself, or insert a skill on a scene object somewhere."""
    if rng.random() < 0.5 and body:
        i = rng.randrange(len(body))
        body.insert(i + 1, body[i])
        return body
    if not pool:
        return None
    body.insert(rng.randrange(len(body) + 1), rng.choice(pool).text)
    return body


def _container_first(task: SeedTask) -> list[str] | None:
    """Movable-receptacle tasks: the container is put on the furniture first, then the object put down there."""
    params = task.pddl_params
    if task.task_type != "pick_and_place_with_movable_recep" or params.object_sliced:
        return None
    parent = "Sink" if params.parent_target == "SinkBasin" else params.parent_target
    obj, mrecep = params.object_target, params.mrecep_target
    steps = [
        Skill(SkillVerb.FIND, mrecep),
        Skill(SkillVerb.PICK_UP, mrecep),
        Skill(SkillVerb.FIND, parent),
        Skill(SkillVerb.PUT_DOWN, mrecep),
        Skill(SkillVerb.FIND, obj),
        Skill(SkillVerb.PICK_UP, obj),
        Skill(SkillVerb.FIND, parent),
        Skill(SkillVerb.PUT_DOWN, obj),
    ]
    return [s.text for s in steps]


def _scene_pools(task: SeedTask) -> tuple[list[str], list[str], list[Skill]]:
    """Pickupable types, receptacle types, and interaction skills on objects of this scene (sorted)."""
    state = initial_state(task)
    pickupable = sorted({s.skill_type for s in state.specs.values() if s.pickupable and "Sliced" not in s.object_type})
    receptacles = sorted({s.skill_type for s in state.specs.values() if s.receptacle and not s.pickupable})
    skills: set[Skill] = set()
    for spec in state.specs.values():
        if "Sliced" in spec.object_type or "synthetic" in spec.object_id:
            continue
        t = spec.skill_type
        if spec.openable:
            skills.update({Skill(SkillVerb.OPEN, t), Skill(SkillVerb.CLOSE, t)})
        if spec.toggleable:
            skills.update({Skill(SkillVerb.TURN_ON, t), Skill(SkillVerb.TURN_OFF, t)})
        if spec.sliceable:
            skills.add(Skill(SkillVerb.SLICE, t))
        if spec.pickupable:
            skills.add(Skill(SkillVerb.PICK_UP, t))
    valid = skill_texts()
    return pickupable, receptacles, sorted((s for s in skills if s.text in valid), key=lambda s: s.text)


def perturb(
    task: SeedTask, reference_plan: Sequence[str], per_kind: int = PERTURBATIONS_PER_KIND
) -> list[PerturbedPlan]:
    """The task's perturbed plans, in kind order; a kind that cannot apply to this plan is skipped."""
    pickupable, receptacles, extra_pool = _scene_pools(task)
    cases: list[PerturbedPlan] = []
    seen: set[tuple[str, ...]] = {tuple(reference_plan)}
    for kind in PerturbationKind:
        for i in range(1 if kind is PerturbationKind.CONTAINER_FIRST else per_kind):
            rng = random.Random(f"{task.task_id}:{kind.value}:{i}")
            body = _body(reference_plan)
            if kind is PerturbationKind.REORDER:
                new = _reorder(rng, body)
            elif kind is PerturbationKind.DROP:
                new = _drop(rng, body)
            elif kind is PerturbationKind.WRONG_OBJECT:
                new = _swap_type(rng, body, {SkillVerb.PICK_UP}, pickupable)
            elif kind is PerturbationKind.WRONG_DESTINATION:
                new = _wrong_destination(rng, body, receptacles)
            elif kind is PerturbationKind.EXTRA:
                new = _extra(rng, body, extra_pool)
            else:
                new = _container_first(task)
            if new is None:
                continue
            plan = (*new, "done")
            if plan in seen:
                continue
            seen.add(plan)
            cases.append(PerturbedPlan(f"{task.task_id}:{kind.value}:{i}", kind, plan))
    return cases
