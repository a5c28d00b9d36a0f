"""The simulated person who answers the planner's questions from the task's gold slots.

Two ways of answering (`CLARIFY_MODES`, `talkdem run --clarify`):

- `oracle`: a clear answer naming the slot asked about and nothing else ("The apple.", "In the fridge.",
  "Heated."), or saying the task has no such slot ("You don't need a light.").
- `in-pattern`: that clear answer spoken under the instruction's own pattern and level, by the dataset's
  generator through its public interface (`talkdem.speech.get_generator`, one `GenerationRequest` with
  the clear answer as the clean text): when the generator is replaced, the answers change wording with it.
  A person who spoke clearly (a clean instruction) answers clearly: the oracle answer.

The generator transforms an utterance around the task's target object. So that a vague reference or a
substitution concerns the object the answer names (the fridge of "In the fridge."), the request carries the
task with the asked slot's type as its target and the other slots' types in the remaining roles: every gold
type stays a task type, which the generator never brings in as a competitor or a drift. An answer must never
name an unasked slot's object (an object-less answer, a state, under a referential pattern would: the
generator then names the target aside); such a draw is redrawn with the next seed, and after `_ATTEMPTS`
draws the clear answer is given and the exchange says so (`in_pattern: false`). "What the task is" reveals
every slot by its nature: it is the instruction's clean control spoken again under the pattern.

Seeds: `derive_seed(PERSON_SEED, episode id, slot, how many times it was asked before, attempt)`: the same
episode asked the same question gives the same bytes; asked again, the person may say it another way.
"""

from __future__ import annotations

import dataclasses
import re
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Literal

from talkdem.clarify.questions import Slot, match_question
from talkdem.schema import CLEAN
from talkdem.skills import categories, natural_name

if TYPE_CHECKING:
    from talkdem.instructions import Instruction
    from talkdem.tasks import Task

__all__ = [
    "CLARIFY_MODES",
    "DONT_KNOW",
    "PERSON_SEED",
    "ClarifyMode",
    "Exchange",
    "SimulatedPerson",
    "leaked_slots",
    "oracle_answer",
    "slot_type",
]

ClarifyMode = Literal["none", "oracle", "in-pattern"]
CLARIFY_MODES: tuple[ClarifyMode, ...] = ("none", "oracle", "in-pattern")
DONT_KNOW = "I don't know."
"""The answer to a question that asks for no slot."""
PERSON_SEED = 23
"""The base of every in-pattern answer's seed (fixed: answers are part of what a run's outcome means)."""
GENERATOR = "rules"
"""The dataset generator whose wording in-pattern answers use (the registry's default name)."""
_ATTEMPTS = 4

_STATES = {
    "pick_heat_then_place_in_recep": "heated",
    "pick_cool_then_place_in_recep": "cooled",
    "pick_clean_then_place_in_recep": "cleaned",
}
_INSIDE = frozenset({"SinkBasin", "BathtubBasin", "GarbageCan", "Bowl", "Cup", "Mug", "Pot", "Pan", "Box"})
_ROLES = ("object_target", "parent_target", "mrecep_target", "toggle_target")
_SLOT_ROLE = {
    Slot.OBJECT: "object_target",
    Slot.DESTINATION: "parent_target",
    Slot.CONTAINER: "mrecep_target",
    Slot.LAMP: "toggle_target",
}


@dataclass(frozen=True)
class Exchange:
    """One question and its answer, as the episode records it."""

    step: int
    """How many actions had been executed when the question was asked."""
    question: str
    """The question as the planner asked it."""
    slot: str
    """The slot it was matched to (`Slot`), or "" for none (answered `DONT_KNOW`)."""
    answer: str
    in_pattern: bool
    """True when the answer was spoken under the instruction's pattern (in-pattern mode, a pattern
    instruction, an answer that names no unasked slot)."""

    def to_json(self) -> dict[str, Any]:
        return dataclasses.asdict(self)


def slot_type(task: Task, slot: Slot) -> str:
    """The object type a slot names in `task` ("" for the state, the task, or a slot the task lacks)."""
    role = _SLOT_ROLE.get(slot)
    return str(getattr(task.pddl_params, role)) if role else ""


def _states(task: Task) -> list[str]:
    states = ["sliced"] if task.pddl_params.object_sliced else []
    if task.task_type in _STATES:
        states.append(_STATES[task.task_type])
    return states


def oracle_answer(task: Task, slot: Slot | None) -> str:
    """The clear answer to a question about `slot` (None: `DONT_KNOW`)."""
    if slot is None:
        return DONT_KNOW
    if slot is Slot.TASK:
        return " ".join(task.instruction.split())
    if slot is Slot.STATE:
        states = _states(task)
        return f"{' and '.join(states).capitalize()}." if states else "It stays as it is."
    kind = slot_type(task, slot)
    if not kind:
        return {
            Slot.OBJECT: DONT_KNOW,  # every task has one; kept for completeness
            Slot.DESTINATION: "You don't need to put it anywhere.",
            Slot.CONTAINER: "You don't need anything to carry it in.",
            Slot.LAMP: "You don't need a light.",
        }[slot]
    name = natural_name(kind)
    if slot is Slot.DESTINATION:
        inside = kind in _INSIDE or kind in categories().openable
        return f"{'In' if inside else 'On'} the {name}."
    if slot is Slot.CONTAINER:
        return f"In the {name}."
    return f"The {name}."


def leaked_slots(task: Task, slot: Slot | None, answer: str) -> list[str]:
    """The gold object types other than the asked slot's that `answer` names (the lexicon's mentions)."""
    from talkdem.speech.lexicon import display_name, mentions_of

    asked = slot_type(task, slot) if slot is not None else ""
    withheld = {str(getattr(task.pddl_params, role)) for role in _ROLES} - {asked, ""}
    if asked:
        # The asked object's own name may contain another slot's ("toilet paper hanger" holds "toilet paper").
        for name in sorted({natural_name(asked), display_name(asked)}, key=len, reverse=True):
            answer = re.sub(re.escape(name), " ", answer, flags=re.IGNORECASE)
    found = []
    for kind in sorted(withheld):
        if any(not asked or asked not in mention.types for mention in mentions_of(answer, kind)):
            found.append(kind)
    return found


def _tidy(text: str) -> str:
    """One line, no space or comma before a sentence end (an aside the generator put last, before the
    short answer's stop), the first letter capitalised."""
    text = " ".join(text.split())
    text = re.sub(r"[,;]\s*([.?!])", r"\1", text)
    text = re.sub(r"\s+([.,?!])", r"\1", text)
    return text[:1].upper() + text[1:]


def _speaking_task(task: Task, slot: Slot, clear: str) -> Task:
    """The task as the generator gets it: the answer as its seed wording, the asked slot's type as target."""
    params = task.pddl_params
    role = _SLOT_ROLE.get(slot)
    swapped = {}
    if role and role != "object_target" and getattr(params, role):
        swapped = {"object_target": getattr(params, role), role: params.object_target}
    return dataclasses.replace(task, instruction=clear, pddl_params=dataclasses.replace(params, **swapped))


@dataclass
class SimulatedPerson:
    """Answers one episode's questions (`ask`), in `mode`, for `instruction`'s task."""

    mode: ClarifyMode
    instruction: Instruction
    task: Task
    generator_name: str = GENERATOR
    _asked: dict[str, int] = field(default_factory=dict)
    _generator: Any = None

    def __post_init__(self) -> None:
        if self.mode not in CLARIFY_MODES or self.mode == "none":
            raise ValueError(f"a simulated person answers in mode 'oracle' or 'in-pattern', not {self.mode!r}")

    def ask(self, question: str, step: int) -> Exchange:
        """Match `question` to a slot and answer it (the same question again counts as a new ask)."""
        slot = match_question(question)
        key = slot.value if slot is not None else ""
        count = self._asked.get(key, 0)
        self._asked[key] = count + 1
        answer, in_pattern = self.answer(slot, count)
        return Exchange(step, " ".join(question.split()), key, answer, in_pattern)

    def answer(self, slot: Slot | None, asked_before: int = 0) -> tuple[str, bool]:
        """(the answer to `slot`, whether it was spoken under the pattern)."""
        clear = oracle_answer(self.task, slot)
        pattern = self.instruction.condition.pattern
        if self.mode == "oracle" or slot is None or pattern == CLEAN:
            return clear, False
        from talkdem.speech import GenerationRequest, derive_seed

        if self._generator is None:
            from talkdem.speech import get_generator

            self._generator = get_generator(self.generator_name)
        level = self.instruction.condition.level
        if slot is Slot.TASK:
            task, text = self.task, self.instruction.clean_text
        else:
            task, text = _speaking_task(self.task, slot, clear), clear
        for attempt in range(1, _ATTEMPTS + 1):
            seed = derive_seed(PERSON_SEED, self.instruction.id, slot.value, asked_before, attempt)
            spoken = self._generator.generate([GenerationRequest(task, pattern, level, text, seed)])[0]
            spoken = _tidy(str(spoken))
            if spoken and (slot is Slot.TASK or not leaked_slots(self.task, slot, spoken)):
                return spoken, True
        return clear, False

    def describe(self) -> str:
        """How this person answers, for the run header."""
        if self.mode == "oracle":
            return "oracle"
        return f"in-pattern ({self.generator_name})"
