"""The sweep spec: a YAML file naming models x strategies x conditions x tasks (and planner settings), read into
one `SweepRun` per (model, strategy), each an ordinary `talkdem run` directory under the spec's output root.

    out: runs/pilot                      # the output root (relative to the current folder, as `--out` is)
    models:
      - smollm2-135m-instruct            # a name of `talkdem models`, a GGUF file, a model id or a served name
      - model: qwen7b
        backend: openai                  # default llamacpp
        label: qwen7b-sglang             # the run folder's prefix (default: the model's file or name)
        args: {base_url: [http://10.0.0.5:30000], tokenizer: Qwen/Qwen2.5-7B-Instruct, scoring_api: sglang}
        model_args: {timeout: 120}       # the backend's own constructor options (`talkdem run --model-arg`)
        ray: {num_cpus: 1}               # the resources of one Ray actor of this model
    strategies: [vanilla, {name: care, args: {care_order: best_last}}]
    conditions: [clean, intrusion:3]     # default: all 16
    tasks: 60                            # stratified over task types; default: all 300
    planner: {type: scoring, max_steps: 10, feedback: message}   # also clarify: oracle, clarify_budget: 2

Every value is validated by `talkdem run`'s own parser and argument checks (`plan_run`), before anything runs:
the keys of `args`, `planner` and a strategy's `args` are `talkdem run`'s option names (`base_url` for
`--base-url`), so a setting means exactly what the flag means, and a bad one is one line naming the file, the
key and what was expected. A model's `model_args` are its backend's constructor options, checked by the backend's
own declaration (`talkdem.llm.interface.options`) and passed as `--model-arg KEY=VALUE`; `threads` is not one of them
here, since the executor gives every worker its share of the CPUs (`talkdem sweep --threads`).

Before any of that, the spec's shape is checked: the file is read through the package's bounded YAML reader
(`talkdem.yaml_input`: no alias bomb, no duplicate key at any depth), every field has the type it must have
(a key given with no value is refused: leave it out for its default), and the grid is bounded
(`MAX_RUNS` runs, `MAX_SHARDS` shards per run), so that a mistake is one line naming the file, the field's path
(`strategies[0].name`) and what was expected, never an exception from deeper down.
"""

from __future__ import annotations

import argparse
import difflib
import functools
import math
import re
import reprlib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

__all__ = [
    "MAX_RUNS",
    "MAX_SHARDS",
    "MODEL_ARGS",
    "PLANNER_ARGS",
    "STRATEGY_ARGS",
    "SweepRun",
    "SweepSpec",
    "SweepSpecError",
    "load_sweep",
    "run_parser",
    "select_runs",
]

MODEL_ARGS = ("base_url", "tokenizer", "scoring_api", "prompt_format", "bos", "concurrency", "timeout")
"""`talkdem run` options a model entry's `args` may set (how the model is reached)."""
PLANNER_ARGS = {
    "type": "planner",
    "max_steps": "max_steps",
    "scoring": "scoring",
    "feedback": "feedback",
    "thought_tokens": "thought_tokens",
    "log_top": "log_top",
    "no_mask_failed": "no_mask_failed",
    "clarify": "clarify",
    "clarify_budget": "clarify_budget",
}
"""`planner:` keys and the `talkdem run` option each sets (`type` is `--planner`)."""
STRATEGY_ARGS = ("care_order", "care_dedupe", "generation_tokens", "generation_plain")
"""`talkdem run` options a strategy entry's `args` may set."""

_TOP_KEYS = ("out", "models", "strategies", "conditions", "tasks", "planner", "shards")
_MODEL_KEYS = ("model", "backend", "label", "args", "model_args", "ray")
_STRATEGY_KEYS = ("name", "label", "args")
_RAY_KEYS = ("num_cpus", "num_gpus")
_LABEL = re.compile(r"[A-Za-z0-9][A-Za-z0-9._-]*")
MAX_RUNS = 1_000
"""Runs (models x strategies) a spec may expand into: each is checked by `talkdem run`'s own planning."""
MAX_SHARDS = 10_000
"""Shards per run a spec may ask for (each is a folder and a job; a run has at most 4,800 episodes)."""
LOCAL_BACKENDS = ("hf", "llamacpp")
"""Backends that compute in the worker's own process: `--threads` applies, and a Ray actor reserves that many
CPUs."""


class SweepSpecError(ValueError):
    """A spec that cannot be run: the message names the file and the key."""


class _Refused(Exception):
    pass


class _RaisingParser(argparse.ArgumentParser):
    """`talkdem run`'s parser, raising instead of exiting, so its message can name the spec's key."""

    def error(self, message: str) -> Any:  # argparse's signature returns NoReturn
        raise _Refused(message)


@functools.cache
def run_parser() -> argparse.ArgumentParser:
    """A parser of `talkdem run ARGS` that raises `ValueError` (not `SystemExit`) on a bad argument."""
    from talkdem.cli import run as run_command

    root = _RaisingParser(prog="talkdem", add_help=False)
    run_command.register(root.add_subparsers(dest="command"))
    return root


def _run_actions() -> dict[str, argparse.Action]:
    parser = run_parser()
    (subparsers,) = (a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return {action.dest: action for action in subparsers.choices["run"]._actions}


@dataclass(frozen=True)
class SweepRun:
    """One (model, strategy) of the sweep: a `talkdem run` directory."""

    name: str
    run_dir: Path
    model: str
    backend: str
    strategy: str
    argv: tuple[str, ...]
    """`talkdem run` arguments, without `--out`, `--shard`, `--threads` and `--no-progress` (the executor's)."""
    episode_ids: tuple[str, ...]
    """The run's selection, in its order."""
    model_index: int
    """Which entry of `models` (a Ray actor holds one model, and serves every strategy of it)."""
    resources: Mapping[str, float] = field(default_factory=dict)
    """A Ray actor's resources as the spec gives them (`num_cpus`, `num_gpus`)."""

    @property
    def local_model(self) -> bool:
        return self.backend in LOCAL_BACKENDS

    def command(self, *, out: Path | None = None, threads: int | None = None, shard: str | None = None) -> list[str]:
        """The `talkdem run` arguments of this run (or of one shard of it); `out` None: the caller adds it."""
        argv = [*self.argv, *(["--out", str(out)] if out is not None else [])]
        if shard:
            argv += ["--shard", shard]
        if threads and self.local_model:
            argv += ["--threads", str(threads)]
        return argv


@dataclass(frozen=True)
class SweepSpec:
    path: Path
    out: Path
    runs: tuple[SweepRun, ...]
    conditions: str | None
    """As `talkdem run --conditions` takes them (None: all 16)."""
    tasks: int | None
    shards: int | None


def _where(path: Path, key: str) -> str:
    return f"{path}: {key}"


def _fail(path: Path, key: str, message: str) -> SweepSpecError:
    return SweepSpecError(f"{_where(path, key)}: {message}")


def _unknown_keys(path: Path, key: str, data: Mapping[str, Any], allowed: Sequence[str]) -> None:
    for name in data:
        if not isinstance(name, str) or name not in allowed:
            shown = name if isinstance(name, str) and len(name) <= 40 else _shown(name)
            close = difflib.get_close_matches(str(name), allowed, n=1)
            hint = f" (did you mean '{close[0]}'?)" if close else ""
            raise _fail(path, f"{key}{shown}", f"unknown key{hint}; expected one of {', '.join(allowed)}")


def _mapping(path: Path, key: str, value: object) -> Mapping[str, Any]:
    if not isinstance(value, Mapping):
        raise _fail(path, key, f"expected a mapping (key: value), got {_kind(value)}")
    return value


def _kind(value: object) -> str:
    if value is None:
        return "nothing"
    return {bool: "true/false", int: "a number", float: "a number", str: "a string", list: "a list"}.get(
        type(value), "a mapping" if isinstance(value, Mapping) else f"a {type(value).__name__}"
    )


_SHOWN = reprlib.Repr()
_SHOWN.maxstring, _SHOWN.maxother, _SHOWN.maxlist, _SHOWN.maxdict, _SHOWN.maxlevel = 40, 40, 4, 4, 2


def _shown(value: object) -> str:
    """`value` as a message shows it: short, whatever the spec holds (a long string, a big nested list)."""
    return _SHOWN.repr(value)


def _scalar(value: object) -> bool:
    """A value a `talkdem run` option or a backend's option can take: text or a number."""
    return isinstance(value, str | int | float) and not isinstance(value, bool)


def _text(path: Path, key: str, value: object) -> str:
    if not isinstance(value, str) or not value.strip():
        raise _fail(path, key, f"expected a non-empty string, got {_kind(value)}")
    return value


def _label(path: Path, key: str, value: object) -> str:
    text = _text(path, key, value)
    if not _LABEL.fullmatch(text):
        raise _fail(path, key, f"'{text}' is not a folder name (letters, digits, '.', '_', '-')")
    return text


def _positive(path: Path, key: str, value: object, most: int) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or not 1 <= value <= most:
        raise _fail(path, key, f"expected a whole number from 1 to {most:,}, got {_shown(value)}")
    return value


def _list(path: Path, key: str, value: object, what: str) -> list[Any]:
    if not isinstance(value, list) or not value:
        raise _fail(path, key, f"expected a non-empty list of {what}, got {_kind(value)}")
    return value


def _flags(path: Path, key: str, values: Mapping[str, Any], names: Mapping[str, str]) -> list[str]:
    """`talkdem run` arguments for `{spec key: value}` (`names`: spec key -> option dest), each value checked
    by the option itself."""
    _unknown_keys(path, key, values, list(names))
    actions = _run_actions()
    argv: list[str] = []
    for name, value in values.items():
        action = actions[names[name]]
        flag = action.option_strings[-1]
        where = f"{key}{name}"
        if action.nargs == 0:  # a switch: true turns it on
            if not isinstance(value, bool):
                raise _fail(path, where, f"expected true or false, got {_kind(value)}")
            given = [flag] if value else []
        else:
            items = value if isinstance(value, list) and isinstance(action, argparse._AppendAction) else [value]
            if not items or not all(_scalar(v) for v in items):
                plural = "a value or a list of values" if isinstance(action, argparse._AppendAction) else "a value"
                wrong = next((v for v in items if not _scalar(v)), value)
                raise _fail(path, where, f"expected {plural} (text or a number), got {_kind(wrong)}")
            given = [part for item in items for part in (flag, str(item))]
        try:
            run_parser().parse_args(["run", *given])
        except _Refused as refused:
            message = str(refused).removeprefix(f"argument {'/'.join(action.option_strings)}: ")
            raise _fail(path, where, message) from None
        argv += given
    return argv


def _conditions(path: Path, value: object) -> str:
    from talkdem.schema import parse_conditions

    expected = "expected a list of conditions (clean, PATTERN, PATTERN:LEVEL; leave the key out for all 16)"
    items = value.split(",") if isinstance(value, str) else value
    if not isinstance(items, list) or not items:
        raise _fail(path, "conditions", f"{expected}, got {_kind(value)}")
    for index, item in enumerate(items):
        if not isinstance(item, str):
            raise _fail(path, f"conditions[{index}]", f"expected a condition (a string), got {_kind(item)}")
    text = ",".join(c.strip() for c in items)
    try:
        parse_conditions(text)
    except ValueError as error:
        raise _fail(path, "conditions", str(error)) from None
    return text


def _tasks(path: Path, value: object) -> int | None:
    if isinstance(value, str) and value == "all":
        return None
    if isinstance(value, bool) or not isinstance(value, int) or value < 1:
        raise _fail(path, "tasks", f"expected a number of tasks (at least 1) or 'all', got {_shown(value)}")
    return value


@dataclass(frozen=True)
class _Model:
    index: int
    model: str
    backend: str
    label: str
    argv: tuple[str, ...]
    resources: dict[str, float]


def _models(path: Path, value: object) -> list[_Model]:
    from talkdem.llm.interface.registry import BACKENDS

    models = []
    for index, entry in enumerate(_list(path, "models", value, "models")):
        key = f"models[{index}]"
        entry = {"model": entry} if isinstance(entry, str) else _mapping(path, key, entry)
        _unknown_keys(path, f"{key}.", entry, _MODEL_KEYS)
        if "model" not in entry:
            raise _fail(path, f"{key}.model", "missing: name the model (`talkdem models`, a file, an id or a name)")
        model = _text(path, f"{key}.model", entry["model"])
        backend = _text(path, f"{key}.backend", entry.get("backend", "llamacpp"))
        if backend not in BACKENDS:
            raise _fail(path, f"{key}.backend", f"expected one of {', '.join(BACKENDS.names())}, got {_shown(backend)}")
        default_label = Path(model).name.removesuffix(".gguf")
        label = _label(path, f"{key}.label", entry.get("label", default_label))
        argv = _flags(path, f"{key}.args.", _mapping(path, f"{key}.args", entry.get("args", {})), _same(MODEL_ARGS))
        argv += _model_args(path, f"{key}.model_args", str(backend), entry.get("model_args", {}))
        ray = _mapping(path, f"{key}.ray", entry.get("ray", {}))
        _unknown_keys(path, f"{key}.ray.", ray, _RAY_KEYS)
        resources: dict[str, float] = {}
        for name, amount in ray.items():
            if (
                isinstance(amount, bool)
                or not isinstance(amount, int | float)
                or not math.isfinite(amount)
                or amount < 0
            ):
                raise _fail(path, f"{key}.ray.{name}", f"expected a number of at least 0, got {_shown(amount)}")
            resources[name] = float(amount)
        models.append(
            _Model(index, model, str(backend), label, ("--model", model, "--backend", backend, *argv), resources)
        )
    return models


def _model_args(path: Path, key: str, backend: str, value: object) -> list[str]:
    """`--model-arg KEY=VALUE` arguments for a model's `model_args` mapping, each value checked by the backend."""
    from talkdem.llm.interface.registry import model_args

    argv: list[str] = []
    for name, setting in _mapping(path, key, value).items():
        where = f"{key}.{name if isinstance(name, str) and len(name) <= 40 else _shown(name)}"
        if not isinstance(name, str) or not name.isidentifier():  # `NAME=VALUE` must split back as it was given
            raise _fail(path, where, f"expected an option name of the {backend} backend, got {_kind(name)}")
        if name == "threads":
            raise _fail(path, where, "set by the executor (`talkdem sweep --threads`, each worker its share of CPUs)")
        if not (_scalar(setting) or isinstance(setting, bool)):
            raise _fail(path, where, f"expected a value (text, a number or true/false), got {_kind(setting)}")
        text = ("true" if setting else "false") if isinstance(setting, bool) else str(setting)
        try:
            model_args(backend, [f"{name}={text}"])
        except ValueError as error:
            raise _fail(path, where, str(error)) from None
        argv += ["--model-arg", f"{name}={text}"]
    return argv


def _same(names: Sequence[str]) -> dict[str, str]:
    return {name: name for name in names}


def _strategies(path: Path, value: object) -> list[tuple[str, str, tuple[str, ...], str]]:
    """(name, label, argv, key) per strategy entry."""
    from talkdem.planner.strategies import STRATEGIES

    strategies = []
    for index, entry in enumerate(_list(path, "strategies", value, "strategies")):
        key = f"strategies[{index}]"
        entry = {"name": entry} if isinstance(entry, str) else _mapping(path, key, entry)
        _unknown_keys(path, f"{key}.", entry, _STRATEGY_KEYS)
        if "name" not in entry:
            raise _fail(path, f"{key}.name", f"missing: one of {', '.join(STRATEGIES.names())}")
        name = _text(path, f"{key}.name", entry["name"])
        if name not in STRATEGIES:
            close = difflib.get_close_matches(name, STRATEGIES.names(), n=1)
            hint = f" (did you mean '{close[0]}'?)" if close else ""
            expected = f"expected one of {', '.join(STRATEGIES.names())}, got {_shown(name)}{hint}"
            raise _fail(path, f"{key}.name", expected)
        label = _label(path, f"{key}.label", entry.get("label", name))
        argv = _flags(path, f"{key}.args.", _mapping(path, f"{key}.args", entry.get("args", {})), _same(STRATEGY_ARGS))
        strategies.append((str(name), label, ("--strategy", str(name), *argv), key))
    return strategies


def load_sweep(path: Path, out: Path | None = None) -> SweepSpec:
    """Read and validate the spec at `path` (`out`: the output root, instead of the spec's `out`)."""
    from talkdem.cli.run import plan_run

    top = _mapping(path, "(top level)", _read(path))
    _unknown_keys(path, "", top, _TOP_KEYS)
    if "out" in top:  # checked even when --out replaces it: a wrong value is a mistake either way
        spec_out = Path(_text(path, "out", top["out"]))
        out = out if out is not None else spec_out
    elif out is None:
        raise _fail(path, "out", "missing: the output root of the sweep's run directories (or give --out)")
    conditions = _conditions(path, top["conditions"]) if "conditions" in top else None
    tasks = _tasks(path, top["tasks"]) if "tasks" in top else None
    shards = _positive(path, "shards", top["shards"], MAX_SHARDS) if "shards" in top else None
    planner_argv = _flags(path, "planner.", _mapping(path, "planner", top.get("planner", {})), PLANNER_ARGS)
    react = "--planner" in planner_argv and planner_argv[planner_argv.index("--planner") + 1] == "react"
    if "models" not in top:
        raise _fail(path, "models", "missing: a list of models")
    if "strategies" not in top:
        raise _fail(path, "strategies", "missing: a list of strategies")
    grid = len(_list(path, "models", top["models"], "models")) * len(
        _list(path, "strategies", top["strategies"], "strategies")
    )
    if grid > MAX_RUNS:  # before each run is planned: every one of them is
        raise _fail(path, "models x strategies", f"{grid:,} runs; a spec expands into at most {MAX_RUNS:,}")
    models = _models(path, top["models"])
    strategies = _strategies(path, top["strategies"])
    selection = [*(["--conditions", conditions] if conditions else []), *(["--limit", str(tasks)] if tasks else [])]
    parser = run_parser()
    runs: list[SweepRun] = []
    named: dict[str, str] = {}
    for model in models:
        for strategy, label, strategy_argv, strategy_key in strategies:
            name = f"{model.label}{'-react' if react else ''}-{label}"
            which = f"models[{model.index}] x {strategy_key}"
            if name in named:
                raise _fail(
                    path,
                    which,
                    f"writes {out / name}, as {named[name]} does: give one of them another label",
                )
            named[name] = which
            argv = (*model.argv, *strategy_argv, *planner_argv, *selection)
            run = SweepRun(
                name, out / name, model.model, model.backend, strategy, argv, (), model.index, model.resources
            )
            try:
                # The run's own checks, as `talkdem run` makes them (threads: as the executor will pass them)
                plan = plan_run(parser.parse_args(["run", *run.command(out=run.run_dir, threads=1), "--no-progress"]))
            except (_Refused, ValueError) as error:
                raise _fail(path, f"{which} ({model.label}, {label})", str(error)) from None
            runs.append(
                SweepRun(
                    name,
                    out / name,
                    model.model,
                    model.backend,
                    strategy,
                    argv,
                    tuple(i.id for i in plan.episodes),
                    model.index,
                    model.resources,
                )
            )
    return SweepSpec(path, out, tuple(runs), conditions, tasks, shards)


def _read(path: Path) -> Any:
    """The spec file's YAML value, read through the bounded reader (the file itself bounded first: a spec
    is a few kilobytes, and a device or a huge file must not be read whole)."""
    from talkdem.yaml_input import MAX_CHARS, YamlInputError, load_yaml

    try:
        with path.open("rb") as handle:
            raw = handle.read(MAX_CHARS + 1)
        if len(raw) > MAX_CHARS:
            raise SweepSpecError(f"{path}: larger than {MAX_CHARS:,} bytes; a sweep spec is a few kilobytes")
        text = raw.decode("utf-8")
    except FileNotFoundError:
        raise SweepSpecError(f"{path}: no such spec file") from None
    except (OSError, UnicodeDecodeError) as error:
        raise SweepSpecError(f"{path}: cannot read the spec ({error})") from None
    try:
        return load_yaml(text)
    except YamlInputError as error:
        where = f"line {error.line}" if error.line is not None else "YAML"
        problem = f"not valid YAML ({error.problem})" if error.syntax else error.problem
        raise SweepSpecError(f"{path}: {where}: {problem}") from None


def select_runs(spec: SweepSpec, names: Sequence[str]) -> SweepSpec:
    """`spec` with only the runs named (their folder names, in the spec's order), so that one sitting can run a
    few of a grid's runs into the same directories the whole grid writes; an unknown name is refused."""
    known = [run.name for run in spec.runs]
    if not names:
        raise SweepSpecError(f"{spec.path}: no run named to select; its runs are {', '.join(known)}")
    for name in names:
        if name not in known:
            close = difflib.get_close_matches(name, known, n=1)
            hint = f" (did you mean '{close[0]}'?)" if close else ""
            raise SweepSpecError(f"{spec.path}: no run named '{name}'{hint}; its runs are {', '.join(known)}")
    wanted = set(names)
    return replace(spec, runs=tuple(run for run in spec.runs if run.name in wanted))
