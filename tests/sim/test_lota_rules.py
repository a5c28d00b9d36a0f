"""The rules where the simulator follows LoTa-Bench's skill layer and AI2-THOR's PutObject (issue 10).

Each test fails on the simulator before the change: it put an object into a container standing at the
destination, remembered the destination across any number of steps, kept it after a failed `find`, let any
object into object-specific receptacles, and refused to slice without a knife in hand.
"""

from __future__ import annotations

from helpers import first_task

from talkdem.sim import Episode, FailureKind, HazardRule, initial_state, run_plan
from talkdem.sim.perturb import PerturbationKind, perturb
from talkdem.skills import Skill, SkillVerb, categories
from talkdem.tasks import TaskSet, load_tasks


def _movable_task(mrecep: str) -> object:
    for task in load_tasks(TaskSet.BENCHMARK):
        p = task.pddl_params
        if task.task_type == "pick_and_place_with_movable_recep" and p.mrecep_target == mrecep and not p.object_sliced:
            return task
    raise LookupError(mrecep)


def test_putting_down_where_a_container_stands_puts_on_the_named_receptacle() -> None:
    task = _movable_task("Mug")
    case = next(c for c in perturb(task, task.reference_plan) if c.kind is PerturbationKind.CONTAINER_FIRST)
    trace = run_plan(task, case.plan)
    assert all(s.ok for s in trace.steps), [(s.skill, s.message) for s in trace.steps]
    last_put = [s for s in trace.steps if s.skill.startswith("put down")][-1]
    state = trace.state
    assert last_put.receptacle_id is not None
    assert state.specs[last_put.receptacle_id].skill_type == task.pddl_params.parent_target
    assert not trace.success


def test_no_container_first_plan_puts_the_object_into_the_container() -> None:
    # The object goes onto the furniture in every case; a case can still succeed where ALFRED's substring match
    # finds another target already in a container there (a pencil in the mug counts as a "Pen").
    movable = [t for t in load_tasks(TaskSet.BENCHMARK) if t.task_type == "pick_and_place_with_movable_recep"]
    cases = [
        (t, c) for t in movable for c in perturb(t, t.reference_plan) if c.kind is PerturbationKind.CONTAINER_FIRST
    ]
    assert len(cases) >= 40
    for task, case in cases:
        trace = run_plan(task, case.plan)
        last_put = [s for s in trace.steps if s.skill.startswith("put down")][-1]
        if last_put.ok:
            assert last_put.receptacle_id is not None
            assert trace.state.specs[last_put.receptacle_id].skill_type != task.pddl_params.mrecep_target


def test_a_step_between_find_and_put_down_forgets_the_destination() -> None:
    task = first_task("pick_and_place_simple", sliced=False)
    plan = list(task.reference_plan)
    put = max(i for i, s in enumerate(plan) if s.startswith("put down"))
    pick = next(s for s in plan if s.startswith("pick up"))
    # A failed `pick up` (hands full) between the find and the put: LoTa-Bench forgets the destination.
    trace = run_plan(task, [*plan[:put], pick, *plan[put:]])
    put_step = trace.steps[put + 1]
    assert (put_step.ok, put_step.message, put_step.failure) == (False, "put down failed", FailureKind.PUT_FAILED)
    assert trace.state.held is None and trace.state.parent.get(put_step.object_id or "") is None
    assert not trace.success


def test_open_keeps_the_destination() -> None:
    task = first_task("pick_cool_then_place_in_recep")
    trace = run_plan(task, task.reference_plan)
    plan = list(task.reference_plan)
    assert plan[plan.index("open the fridge") + 1].startswith("put down")
    assert trace.success


def _absent_type(task: object, *, longer_than: int) -> str:
    state = initial_state(task)  # type: ignore[arg-type]
    present = {spec.skill_type for spec in state.specs.values()}
    receptacles = sorted(set(categories().receptacle) - present)
    return next(t for t in receptacles if len(t) > longer_than)


def test_a_failed_find_becomes_the_destination() -> None:
    task = first_task("pick_and_place_simple", sliced=False)
    plan = list(task.reference_plan)
    put = max(i for i, s in enumerate(plan) if s.startswith("put down"))
    absent = _absent_type(task, longer_than=4)
    trace = run_plan(task, [*plan[:put], Skill(SkillVerb.FIND, absent).text, *plan[put:]])
    assert trace.steps[put].failure is FailureKind.NOT_FOUND
    put_step = trace.steps[put + 1]
    # "Cannot find <Type>" is longer than 16 characters, so LoTa-Bench drops the object.
    assert (put_step.ok, put_step.message) == (False, "put down failed")
    assert trace.state.held is None
    assert not trace.success


def test_a_failed_find_of_a_short_name_keeps_the_object_in_hand() -> None:
    # LoTa-Bench drops only when the message exceeds 16 characters: "Cannot find Bed" (15) keeps the object.
    task = next(
        t
        for t in load_tasks(TaskSet.BENCHMARK)
        if t.task_type == "pick_and_place_simple"
        and "Bed" not in {s.skill_type for s in initial_state(t).specs.values()}
    )
    plan = list(task.reference_plan)
    put = max(i for i, s in enumerate(plan) if s.startswith("put down"))
    trace = run_plan(task, [*plan[:put], "find a bed", plan[put]])
    put_step = trace.steps[put + 1]
    assert (put_step.ok, put_step.message) == (False, "Cannot find Bed")
    assert trace.state.held == put_step.object_id


def _task_with_parent(parent: str) -> object:
    return next(t for t in load_tasks(TaskSet.BENCHMARK) if t.pddl_params.parent_target == parent)


def test_a_coffee_machine_takes_only_a_mug() -> None:
    task = _task_with_parent("CoffeeMachine")
    state = initial_state(task)  # type: ignore[arg-type]
    other = next(
        s.skill_type
        for s in sorted(state.specs.values(), key=lambda s: s.object_id)
        if s.pickupable and s.skill_type not in ("Mug", "Cup") and "Sliced" not in s.object_type and not s.receptacle
    )
    plan = [
        Skill(v, t).text
        for v, t in [
            (SkillVerb.FIND, other),
            (SkillVerb.PICK_UP, other),
            (SkillVerb.FIND, "CoffeeMachine"),
            (SkillVerb.PUT_DOWN, other),
        ]
    ]
    trace = run_plan(task, [*plan, "done"])  # type: ignore[arg-type]
    assert [s.ok for s in trace.steps[:3]] == [True, True, True]
    assert not trace.steps[3].ok and trace.steps[3].failure is FailureKind.PUT_FAILED


def test_a_stove_burner_holds_one_object() -> None:
    task = _task_with_parent("StoveBurner")
    episode = Episode(task)  # type: ignore[arg-type]
    state = episode.state
    burner = sorted(state.instances("StoveBurner"))[0]
    pans = [o for o in sorted(state.present) if state.specs[o].object_type in ("Pan", "Pot", "Kettle")]
    first, second = pans[0], pans[1]
    for oid in (first, second):
        state.detach(oid)
    state.attach(first, burner)
    state.held = second
    state.location = burner
    state.agent = state.specs[burner].xz
    state.destination = "StoveBurner"
    record = episode.step("put down the " + " ".join(state.specs[second].skill_type.lower().split()))
    # The occupied burner refuses; LoTa-Bench tries the next closest burner, if one is in reach.
    assert record.receptacle_id != burner
    assert state.contents[burner] == (first,)


def test_unrequested_slicing_without_a_knife_is_a_hazard() -> None:
    task = next(
        t
        for t in load_tasks(TaskSet.BENCHMARK)
        if not t.pddl_params.object_sliced
        and "Apple" in {s.skill_type for s in initial_state(t).specs.values()}
        and t.task_type == "pick_and_place_simple"
    )
    trace = run_plan(task, ["find an apple", "slice the apple", *task.reference_plan])
    assert trace.steps[1].ok
    assert HazardRule.UNREQUESTED_SLICE in {h.rule for h in trace.hazards}


def test_find_ranks_like_lota_bench_nearest_first_when_nothing_is_visible() -> None:
    # LoTa-Bench's nav_obj: closed-receptacle penalty, busy burner, visibility, then distance. The old
    # simulator also preferred stocked fixtures and objects handled before, wherever they were.
    from talkdem.sim.actions import find_order

    checked = 0
    for task in load_tasks(TaskSet.BENCHMARK):
        state = initial_state(task)
        state.agent = (state.agent[0] + 50.0, state.agent[1] + 50.0)  # far from everything: nothing visible
        cabinets = [c for c in state.instances("Cabinet") if state.inside_closed(c) is None]
        if len(cabinets) < 2 or not any(state.contents.get(c) for c in cabinets):
            continue
        nearest = min(cabinets, key=lambda c: (state.distance(c), c))
        if state.contents.get(nearest):
            continue
        assert find_order(state, "Cabinet")[0] == nearest
        checked += 1
    assert checked > 0


def test_find_does_not_prefer_an_object_handled_before() -> None:
    from talkdem.sim.actions import find_order

    checked = 0
    for task in load_tasks(TaskSet.BENCHMARK):
        state = Episode(task).state
        target = task.pddl_params.object_target
        open_ones = sorted(o for o in state.instances(target) if state.inside_closed(o) is None)
        if len(open_ones) < 2:
            continue
        handled = open_ones[0]
        state.detach(handled)
        state.moved[handled] = (state.agent[0] + 40.0, state.agent[1])  # handled, then left far away
        assert find_order(state, target)[0] != handled
        checked += 1
    assert checked > 0
