"""Backend and strategy options as data: each backend declares the constructor options a user may set
(`--model-arg KEY=VALUE`, a sweep spec's `model_args:`), each strategy likewise (`--strategy-arg KEY=VALUE`, a
sweep strategy's `args:`), and one parser turns `key=value` text into typed values through that declaration.

A backend class lists its options in `LanguageModel.options`, beside its constructor, so what a user can set is
read from the backend itself: an unknown key or a bad value is one line naming the option, the backend and what it
accepts, before any model is loaded.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Literal

__all__ = [
    "BackendOption",
    "OptionKind",
    "OptionValue",
    "parse_model_args",
    "parse_option",
    "parse_options",
]

OptionKind = Literal["int", "float", "bool", "str", "choice"]
OptionValue = str | int | float | bool | None
"""What an option's value may be once parsed (None: a choice that means "the backend's own default")."""

_TRUE = ("true", "yes", "on", "1")
_FALSE = ("false", "no", "off", "0")


@dataclass(frozen=True)
class BackendOption:
    """One constructor keyword a user may set, with the type its text is parsed to."""

    name: str
    """The constructor's keyword (and the KEY of `--model-arg KEY=VALUE`)."""
    kind: OptionKind
    help: str = ""
    minimum: float | None = None
    """The smallest value an int or float option accepts."""
    above_minimum: bool = False
    """True: the value must be strictly greater than `minimum` (a timeout of 0 waits for nothing)."""
    choices: Mapping[str, OptionValue] = field(default_factory=dict)
    """For a `choice` option: the text a user writes -> the value the constructor gets."""

    def accepted(self) -> str:
        """What the option takes, in words (for an error message and for help)."""
        if self.kind == "choice":
            return "one of " + ", ".join(self.choices)
        if self.kind == "bool":
            return "true or false"
        if self.kind == "str":
            return "a non-empty string"
        number = "a whole number" if self.kind == "int" else "a number"
        if self.minimum is None:
            return number
        bound = int(self.minimum) if self.kind == "int" else self.minimum
        return f"{number} {'above' if self.above_minimum else 'of at least'} {bound}"

    def parse(self, text: str) -> OptionValue:
        """The typed value of `text`; ValueError (a fragment: what was expected) when it is not one."""
        value: OptionValue
        if self.kind == "choice":
            if text not in self.choices:
                raise ValueError(self.accepted())
            return self.choices[text]
        if self.kind == "bool":
            if text.lower() not in (*_TRUE, *_FALSE):
                raise ValueError(self.accepted())
            return text.lower() in _TRUE
        if self.kind == "str":
            if not text.strip():
                raise ValueError(self.accepted())
            return text
        try:
            value = int(text) if self.kind == "int" else float(text)
        except ValueError:
            raise ValueError(self.accepted()) from None
        if value != value or value in (float("inf"), float("-inf")):  # nan and inf are no setting
            raise ValueError(self.accepted())
        if self.minimum is not None and (value <= self.minimum if self.above_minimum else value < self.minimum):
            raise ValueError(self.accepted())
        return value

    def text(self, value: OptionValue) -> str:
        """The text a user writes for `value` (the inverse of `parse`, for choices: the choice's name)."""
        if self.kind == "choice":
            for name, choice in self.choices.items():
                if choice == value and type(choice) is type(value):
                    return name
        if isinstance(value, bool):
            return "true" if value else "false"
        return str(value)


def _split(item: str, flag: str) -> tuple[str, str]:
    key, sep, value = item.partition("=")
    if not sep or not key.strip():
        raise ValueError(f"{flag} {item!r}: expected KEY=VALUE")
    return key.strip(), value.strip()


def parse_option(
    options: Sequence[BackendOption],
    key: str,
    text: str,
    *,
    owner: str,
    what: str = "model arg",
    elsewhere: Callable[[str], Sequence[str]] | None = None,
) -> OptionValue:
    """The typed value of option `key` of `owner` (`the hf backend`, `the care strategy`) given as `text`;
    ValueError (one line naming the option, its owner and what it accepts) for an unknown key or a bad value.
    `elsewhere(key)` names the others that declare a key `owner` lacks (the message then says who has it)."""
    declared = {option.name: option for option in options}
    if key not in declared:
        known = ", ".join(declared) or "none"
        others = list(elsewhere(key)) if elsewhere else []
        hint = f"; {' and '.join(others)} {'has' if len(others) == 1 else 'have'} it" if others else ""
        raise ValueError(f"{what} '{key}': {owner} has no such option (its options: {known}){hint}")
    option = declared[key]
    try:
        return option.parse(text)
    except ValueError as error:
        raise ValueError(f"{what} {key}={text!r}: {owner}'s '{key}' takes {error}") from None


def parse_options(
    options: Sequence[BackendOption],
    items: Iterable[str],
    *,
    owner: str,
    what: str = "model arg",
    flag: str = "--model-arg",
    elsewhere: Callable[[str], Sequence[str]] | None = None,
) -> dict[str, OptionValue]:
    """`{key: typed value}` of `KEY=VALUE` strings, in the order given; a key given twice with two values is an
    error (which one would the run use?)."""
    parsed: dict[str, OptionValue] = {}
    for item in items:
        key, text = _split(item, flag)
        value = parse_option(options, key, text, owner=owner, what=what, elsewhere=elsewhere)
        if key in parsed and parsed[key] != value:
            raise ValueError(f"{what} '{key}' given twice, as {parsed[key]!r} and {value!r}: give it once")
        parsed[key] = value
    return parsed


def parse_model_args(backend: str, options: Sequence[BackendOption], items: Iterable[str]) -> dict[str, OptionValue]:
    """`--model-arg KEY=VALUE` strings as `backend`'s typed options (`parse_options` for a backend)."""
    return parse_options(options, items, owner=f"the {backend} backend")
