"""The run configuration: what `talkdem run` is asked to do, as one typed value, whoever asks.

`RunConfig` holds the model and its backend's options, the servers and the episodes in flight, the strategy and
its options, the planner's settings (clarification included), the selection and where the run goes. The CLI
builds one from its parsed flags (`RunConfig.from_namespace`), a sweep from its spec's YAML values
(`RunConfig.from_mapping`); `talkdem.runs.plan` turns it into the run (`plan_run`, `run_config`), and
`RunConfig.arguments` writes it back as the `talkdem run` arguments that mean the same run (a sweep's local
workers start those).

Every value is checked here: a backend option by the backend's declaration (`--model-arg KEY=VALUE`), a strategy
option by the strategy's (`--strategy-arg KEY=VALUE`), the rest by the rules below; a bad one is a
`RunConfigError` naming the setting (`max_steps`, `model_args.n_ctx`), so a sweep can name its spec's key.
"""

from __future__ import annotations

import argparse
import difflib
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Any, Literal, get_args

from talkdem.llm.interface.options import OptionValue
from talkdem.llm.interface.registry import DEFAULT_BACKEND
from talkdem.sim.seam import DEFAULT_MAX_STEPS

__all__ = [
    "CLARIFY_MODES",
    "DEFAULT_CLARIFY_BUDGET",
    "DEFAULT_THOUGHT_TOKENS",
    "FEEDBACKS",
    "PLANNERS",
    "SCORINGS",
    "Clarify",
    "RunConfig",
    "RunConfigError",
    "kind_of",
]

PLANNERS = ("scoring", "generative", "react")
SCORINGS = ("sum", "mean")
FEEDBACKS = ("mask", "message", "both", "none")
Clarify = Literal["none", "oracle", "in-pattern"]
CLARIFY_MODES: tuple[Clarify, ...] = get_args(Clarify)
DEFAULT_CLARIFY_BUDGET = 2
"""Questions per episode with clarification on (KnowNo and DialFRED ask about that often per task)."""
DEFAULT_THOUGHT_TOKENS = 24


class RunConfigError(ValueError):
    """A setting that cannot be run: `key` names it (`max_steps`, `strategy_args.order`), `problem` says why."""

    def __init__(self, key: str, problem: str) -> None:
        super().__init__(f"{key}: {problem}")
        self.key = key
        self.problem = problem


@dataclass(frozen=True)
class RunConfig:
    """One `talkdem run`, every setting typed and checked (the defaults are the command's)."""

    model: str = "default"
    """A name of `talkdem models`, a file, a model id or a served model's name."""
    backend: str = DEFAULT_BACKEND
    model_args: Mapping[str, OptionValue] = field(default_factory=dict)
    """The backend's constructor options, typed by its declaration, in the order given."""
    base_urls: tuple[str, ...] = ()
    """openai backend: the servers, episodes spread over them (none: the backend's default)."""
    concurrency: int = 1
    strategy: str = "vanilla"
    strategy_args: Mapping[str, OptionValue] = field(default_factory=dict)
    """The strategy's constructor options, typed by its declaration."""
    planner: str = "scoring"
    max_steps: int = DEFAULT_MAX_STEPS
    scoring: str = "sum"
    feedback: str = "message"
    thought_tokens: int = DEFAULT_THOUGHT_TOKENS
    log_top: int = 0
    clarify: Clarify = "none"
    clarify_budget: int | None = None
    """None: `DEFAULT_CLARIFY_BUDGET` when clarification is on."""
    conditions: str | None = None
    """As `--conditions` takes them (None: all 16)."""
    limit: int | None = None
    shard: str | None = None
    out: Path | None = None
    cache: Path | None = None
    continue_on_new_revision: bool = False
    progress: bool = True

    @classmethod
    def from_namespace(cls, args: argparse.Namespace) -> RunConfig:
        """The run `talkdem run`'s parsed flags describe (a flag the namespace lacks takes its default); the
        `--model-arg` and `--strategy-arg` items are typed here by the backend's and the strategy's declaration."""
        from talkdem.llm.interface.registry import model_args
        from talkdem.planner.strategies import strategy_args

        given = vars(args)
        values: dict[str, Any] = {
            f.name: given[f.name] for f in fields(cls) if f.name in given and given[f.name] is not None
        }
        backend = values.get("backend", DEFAULT_BACKEND)
        values["model_args"] = model_args(backend, given.get("model_arg") or [])
        values["strategy_args"] = strategy_args(values.get("strategy", "vanilla"), given.get("strategy_arg") or [])
        values["base_urls"] = tuple(given.get("base_url") or ())
        if given.get("no_progress"):
            values["progress"] = False
        config = cls(**values)
        config.check()
        return config

    @classmethod
    def from_mapping(cls, values: Mapping[str, object]) -> RunConfig:
        """The run a mapping of settings describes, as a sweep spec's YAML gives them: keys are the field names,
        values text, numbers or true/false (`base_urls` also a list, `model_args` and `strategy_args` mappings
        of option name to value); each is checked and typed, a bad one is a `RunConfigError` naming its key."""
        unknown = [key for key in values if key not in _READERS]
        if unknown:
            raise RunConfigError(str(unknown[0]), f"not a run setting (known: {', '.join(_READERS)})")
        typed = {key: _READERS[key](key, value) for key, value in values.items() if key not in _OPTIONS}
        backend = str(typed.get("backend", DEFAULT_BACKEND))
        strategy = str(typed.get("strategy", "vanilla"))
        typed["model_args"] = _options("model_args", values.get("model_args", {}), _backend_parser(backend))
        typed["strategy_args"] = _options("strategy_args", values.get("strategy_args", {}), _strategy_parser(strategy))
        config = cls(**typed)
        config.check()
        return config

    def check(self) -> None:
        """Refuse a combination the run cannot mean (a ValueError naming the flags)."""
        if self.clarify == "none" and self.clarify_budget is not None:
            raise ValueError("--clarify-budget applies with --clarify oracle or in-pattern")

    @property
    def questions(self) -> int:
        """Questions allowed per episode (0: clarification off)."""
        return 0 if self.clarify == "none" else (self.clarify_budget or DEFAULT_CLARIFY_BUDGET)

    def arguments(self) -> list[str]:
        """The `talkdem run` arguments of this run: every setting that is not the command's default."""
        from talkdem.llm.interface.registry import backend_options
        from talkdem.planner.strategies import strategy_options

        argv = ["--model", self.model, "--backend", self.backend]
        argv += _option_arguments("--model-arg", self.model_args, backend_options(self.backend))
        for url in self.base_urls:
            argv += ["--base-url", url]
        argv += ["--strategy", self.strategy]
        if self.strategy_args:
            argv += _option_arguments("--strategy-arg", self.strategy_args, strategy_options(self.strategy))
        for f in fields(self):
            if f.name in _NOT_FLAGS or getattr(self, f.name) == f.default:
                continue
            flag, value = f"--{f.name.replace('_', '-')}", getattr(self, f.name)
            argv += [flag] if value is True else [flag, str(value)]
        return [*argv, *([] if self.progress else ["--no-progress"])]


_NOT_FLAGS = frozenset({"model", "backend", "model_args", "base_urls", "strategy", "strategy_args", "progress"})
"""Fields `arguments` writes first or otherwise (every other one is `--NAME-WITH-DASHES [VALUE]`)."""


def _option_arguments(flag: str, values: Mapping[str, OptionValue], declared: Sequence[Any]) -> list[str]:
    by_name = {option.name: option for option in declared}
    return [part for name, value in values.items() for part in (flag, f"{name}={by_name[name].text(value)}")]


def kind_of(value: object) -> str:
    """What a YAML value is, in words (for a message: "expected ..., got a list")."""
    if value is None:
        return "nothing"
    return {bool: "true/false", int: "a number", float: "a number", str: "a string", list: "a list"}.get(
        type(value), "a mapping" if isinstance(value, Mapping) else f"a {type(value).__name__}"
    )


def _scalar(value: object) -> bool:
    return isinstance(value, str | int | float) and not isinstance(value, bool)


def _text(key: str, value: object) -> str:
    if not _scalar(value):
        raise RunConfigError(key, f"expected a value (text or a number), got {kind_of(value)}")
    return str(value)


def _whole(minimum: int) -> Callable[[str, object], int]:
    def read(key: str, value: object) -> int:
        text = _text(key, value)
        try:
            number = int(text)
        except ValueError:
            raise RunConfigError(key, f"'{text}' is not a whole number") from None
        if number < minimum:
            raise RunConfigError(key, f"must be {'at least 1' if minimum else '0 or more'}, got {number}")
        return number

    return read


def _one_of(choices: Sequence[str]) -> Callable[[str, object], str]:
    def read(key: str, value: object) -> str:
        text = _text(key, value)
        if text not in choices:
            raise RunConfigError(key, f"invalid choice: '{text}' (choose from {', '.join(choices)})")
        return text

    return read


def _named(names: Callable[[], Sequence[str]]) -> Callable[[str, object], str]:
    def read(key: str, value: object) -> str:
        text = _nonempty(key, value)
        known = names()
        if text not in known:
            close = difflib.get_close_matches(text, known, n=1)
            hint = f" (did you mean '{close[0]}'?)" if close else ""
            raise RunConfigError(key, f"expected one of {', '.join(known)}, got {text[:40]!r}{hint}")
        return text

    return read


def _nonempty(key: str, value: object) -> str:
    if not isinstance(value, str) or not value.strip():
        raise RunConfigError(key, f"expected a non-empty string, got {kind_of(value)}")
    return value


def _switch(key: str, value: object) -> bool:
    if not isinstance(value, bool):
        raise RunConfigError(key, f"expected true or false, got {kind_of(value)}")
    return value


def _urls(key: str, value: object) -> tuple[str, ...]:
    items = value if isinstance(value, list) else [value]
    if not items or not all(_scalar(v) for v in items):
        wrong = next((v for v in items if not _scalar(v)), value)
        raise RunConfigError(key, f"expected a value or a list of values (text or a number), got {kind_of(wrong)}")
    return tuple(str(item) for item in items)


def _path(key: str, value: object) -> Path:
    return Path(_nonempty(key, value))


def _backend_names() -> Sequence[str]:
    from talkdem.llm.interface.registry import BACKENDS

    return BACKENDS.names()


def _strategy_names() -> Sequence[str]:
    from talkdem.planner.strategies import STRATEGIES

    return STRATEGIES.names()


_READERS: dict[str, Callable[[str, object], Any]] = {
    "model": lambda key, value: _nonempty(key, value),
    "backend": _named(_backend_names),
    "model_args": lambda key, value: value,
    "base_urls": _urls,
    "concurrency": _whole(1),
    "strategy": _named(_strategy_names),
    "strategy_args": lambda key, value: value,
    "planner": _one_of(PLANNERS),
    "max_steps": _whole(1),
    "scoring": _one_of(SCORINGS),
    "feedback": _one_of(FEEDBACKS),
    "thought_tokens": _whole(1),
    "log_top": _whole(0),
    "clarify": _one_of(CLARIFY_MODES),
    "clarify_budget": _whole(1),
    "conditions": lambda key, value: _nonempty(key, value),
    "limit": _whole(1),
    "shard": lambda key, value: _nonempty(key, value),
    "out": _path,
    "cache": _path,
    "continue_on_new_revision": _switch,
    "progress": _switch,
}
"""How `from_mapping` reads each setting (the option mappings are typed by their owner's declaration)."""
_OPTIONS = ("model_args", "strategy_args")


def _backend_parser(backend: str) -> Callable[[list[str]], dict[str, OptionValue]]:
    from talkdem.llm.interface.registry import model_args

    return lambda items: model_args(backend, items)


def _strategy_parser(strategy: str) -> Callable[[list[str]], dict[str, OptionValue]]:
    from talkdem.planner.strategies import strategy_args

    return lambda items: strategy_args(strategy, items)


def _options(key: str, value: object, parse: Callable[[list[str]], dict[str, OptionValue]]) -> dict[str, OptionValue]:
    """A mapping of option name to value, typed one option at a time (so a refusal names its option)."""
    if not isinstance(value, Mapping):
        raise RunConfigError(key, f"expected a mapping (key: value), got {kind_of(value)}")
    typed: dict[str, OptionValue] = {}
    for name, setting in value.items():
        where = f"{key}.{name}"
        if not isinstance(name, str) or not name.isidentifier():  # `NAME=VALUE` must split back as it was given
            raise RunConfigError(where, f"expected an option name, got {kind_of(name)}")
        if not (_scalar(setting) or isinstance(setting, bool)):
            raise RunConfigError(where, f"expected a value (text, a number or true/false), got {kind_of(setting)}")
        text = ("true" if setting else "false") if isinstance(setting, bool) else str(setting)
        try:
            typed.update(parse([f"{name}={text}"]))
        except ValueError as error:
            raise RunConfigError(where, str(error)) from None
    return typed
