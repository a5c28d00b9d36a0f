"""Reference plans converted from the expert trajectories of all 1,000 seeds."""

from __future__ import annotations

import dataclasses

import pytest

from talkdem.seeds import Interaction, SeedTask
from talkdem.skills import skill_texts
from talkdem.tasks import ReferencePlanError, object_type_of, reference_plan


def test_every_seed_converts_into_vocabulary_skills(seed_pool: list[SeedTask]) -> None:
    vocabulary = skill_texts()
    for seed in seed_pool:
        plan = reference_plan(seed)
        assert plan[-1] == "done" and plan.count("done") == 1, seed.source_file
        assert set(plan) <= vocabulary, seed.source_file
        assert len(plan) <= 30, seed.source_file


def test_object_types_of_basins_and_slices() -> None:
    assert object_type_of("Sink|-00.70|+00.93|-00.65|SinkBasin") == "Sink"
    assert object_type_of("Bathtub|-01.20|+00.30|+00.50|BathtubBasin") == "Bathtub"
    assert object_type_of("Apple|-02.31|+00.58|-01.85|AppleSliced_1") == "Apple"
    assert object_type_of("DeskLamp|+01.87|+00.55|+02.42") == "DeskLamp"


def _by_file(seed_pool: list[SeedTask], fragment: str) -> SeedTask:
    return next(s for s in seed_pool if fragment in s.source_file)


def test_cool_episode_has_no_find_while_the_object_is_in_the_fridge(seed_pool: list[SeedTask]) -> None:
    seed = next(
        s
        for s in seed_pool
        if s.task_type == "pick_cool_then_place_in_recep"
        and [i.action for i in s.interactions][:4] == ["PickupObject", "OpenObject", "PutObject", "CloseObject"]
    )
    plan = reference_plan(seed)
    opened = plan.index("open the fridge")
    closed_with_object_inside = plan.index("close the fridge", opened)
    taken_out = next(i for i, s in enumerate(plan) if s.startswith("pick up") and i > closed_with_object_inside)
    between = plan[closed_with_object_inside:taken_out]
    assert between == ["close the fridge", "open the fridge"], plan
    assert not any(step.startswith("find") for step in between)


def test_heat_sliced_episode(seed_pool: list[SeedTask]) -> None:
    seed = _by_file(seed_pool, "pick_heat_then_place_in_recep-AppleSliced-None-Fridge-11/trial_T20190909_060541")
    assert reference_plan(seed)[:9] == [
        "find a butter knife",
        "pick up the butter knife",
        "find a fridge",
        "open the fridge",
        "slice the apple",  # the apple is in the open fridge: no find
        "close the fridge",
        "open the fridge",
        # LoTa-Bench forgot the fridge as destination at `slice` and `close`: the expert walks back to it.
        "find a fridge",
        "put down the butter knife",
    ]


def test_find_precedes_each_change_of_object(seed_pool: list[SeedTask]) -> None:
    seed = next(s for s in seed_pool if s.task_type == "pick_and_place_simple" and len(s.interactions) == 2)
    plan = reference_plan(seed)
    target = seed.pddl_params.object_target
    assert plan[0].startswith("find") and plan[1].startswith("pick up")
    assert plan[2].startswith("find") and plan[3].startswith("put down")
    assert target.lower()[:3] in plan[1].replace(" ", "").lower()


def test_untranslatable_interaction_raises_with_task_and_step(seed_pool: list[SeedTask]) -> None:
    seed = seed_pool[0]
    broken = dataclasses.replace(seed, interactions=(Interaction("ToggleObjectOn", "StoveKnob|+01.00|+00.90|+00.10"),))
    with pytest.raises(ReferencePlanError, match=rf"{seed.task_id}.*interaction 0.*turn on the stove knob"):
        reference_plan(broken)
