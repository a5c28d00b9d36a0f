"""One-sentence task interpretations from the gold task specification (CARE's memory bank, `tasks` config)."""

from __future__ import annotations

from talkdem.seeds.records import PddlParams
from talkdem.skills import natural_name

__all__ = ["interpretation"]

_INSIDE = frozenset(
    {
        "Fridge",
        "Microwave",
        "GarbageCan",
        "SinkBasin",
        "BathtubBasin",
        "Cabinet",
        "Drawer",
        "Safe",
        "Box",
        "Bowl",
        "Mug",
        "Cup",
        "Pot",
        "Pan",
        "Cart",
    }
)


def _place(kind: str) -> str:
    return f"{'in' if kind in _INSIDE else 'on'} the {natural_name(kind)}"


def interpretation(task_type: str, params: PddlParams) -> str:
    """`pick_heat_then_place_in_recep`, Apple -> CounterTop: "Heat an apple in the microwave and put it on ..."."""
    obj = natural_name(params.object_target)
    thing = f"a slice of {obj}" if params.object_sliced else f"the {obj}"
    templates = {
        "look_at_obj_in_light": "Pick up {thing} and turn on the {lamp} to look at it under its light.",
        "pick_and_place_with_movable_recep": "Put {thing} {in_mrecep}, then put the {mrecep} {place}.",
        "pick_clean_then_place_in_recep": "Rinse {thing} in the sink, then put it {place}.",
        "pick_heat_then_place_in_recep": "Heat {thing} in the microwave, then put it {place}.",
        "pick_cool_then_place_in_recep": "Chill {thing} in the fridge, then put it {place}.",
        "pick_and_place_simple": "Put {thing} {place}.",
    }
    if task_type not in templates:
        raise ValueError(f"unknown ALFRED task type '{task_type}'")
    sentence = templates[task_type].format(
        thing=thing,
        lamp=natural_name(params.toggle_target) if params.toggle_target else "lamp",
        mrecep=natural_name(params.mrecep_target) if params.mrecep_target else "",
        in_mrecep=_place(params.mrecep_target) if params.mrecep_target else "",
        place=_place(params.parent_target) if params.parent_target else "",
    )
    if params.object_sliced:
        return f"Slice the {obj} with a knife, then {sentence[:1].lower()}{sentence[1:]}"
    return sentence
