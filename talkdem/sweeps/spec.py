"""The sweep spec: a YAML file naming models x strategies x conditions x tasks (and planner settings), read into
one `SweepRun` per (model, strategy), each an ordinary `talkdem run` directory under the spec's output root.

    out: runs/pilot                      # the output root (relative to the current folder, as `--out` is)
    models:
      - smollm2-135m-instruct            # a name of `talkdem models`, a GGUF file, a model id or a served name
      - model: qwen7b
        backend: openai                  # default llamacpp
        label: qwen7b-sglang             # the run folder's prefix (default: the model's file or name)
        args: {base_url: [http://10.0.0.5:30000], concurrency: 4}
        model_args: {tokenizer: Qwen/Qwen2.5-7B-Instruct, timeout: 120}   # the backend's options (`--model-arg`)
        ray: {num_cpus: 1}               # the resources of one Ray actor of this model
    strategies: [vanilla, {name: care, args: {order: best_last}}]        # the strategy's options (`--strategy-arg`)
    conditions: [clean, intrusion:3]     # default: all 16
    tasks: 60                            # stratified over task types; default: all 300
    planner: {type: scoring, max_steps: 10, feedback: message}   # also clarify: oracle, clarify_budget: 2

Each (model, strategy) becomes one `talkdem.runs.config.RunConfig`, checked and planned as `talkdem run` would
(`plan_run`), before anything runs, without the command line: a model's `args` are how it is reached (`base_url`,
`concurrency`), its `model_args` its backend's constructor options, checked by the backend's own declaration;
a strategy's `args` are its options, checked by the strategy's declaration; `planner` keys are the planner's
settings (`type` is `--planner`). A bad value is one line naming the file, the key and what was expected.
`threads` is no model arg here, since the executor gives every worker its share of the CPUs (`talkdem sweep
--threads`). Older spellings still read: a model's `args` may name the backend options that once had flags of
their own (`tokenizer`, `scoring_api`, `prompt_format`, `bos`, `timeout`), a strategy's `args` the strategy flags'
names (`care_order`, `care_dedupe`, `generation_tokens`, `generation_plain`).

Before any of that, the spec's shape is checked: the file is read through the package's bounded YAML reader
(`talkdem.yaml_input`: no alias bomb, no duplicate key at any depth), every field has the type it must have
(a key given with no value is refused: leave it out for its default), and the grid is bounded
(`MAX_RUNS` runs, `MAX_SHARDS` shards per run), so that a mistake is one line naming the file, the field's path
(`strategies[0].name`) and what was expected, never an exception from deeper down.
"""

from __future__ import annotations

import difflib
import math
import re
import reprlib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from talkdem.llm.interface.registry import DEFAULT_BACKEND, LOCAL_BACKENDS
from talkdem.runs.config import RunConfig, RunConfigError, kind_of

__all__ = [
    "MAX_RUNS",
    "MAX_SHARDS",
    "MODEL_ARGS",
    "PLANNER_ARGS",
    "STRATEGY_ALIASES",
    "SweepRun",
    "SweepSpec",
    "SweepSpecError",
    "load_sweep",
    "select_runs",
]

MODEL_ARGS = {
    "base_url": "base_urls",
    "concurrency": "concurrency",
    "tokenizer": "model_args.tokenizer",
    "scoring_api": "model_args.scoring_api",
    "prompt_format": "model_args.prompt_format",
    "bos": "model_args.add_bos",
    "timeout": "model_args.timeout",
}
"""A model entry's `args` keys and the run setting each sets (the backend options among them are the ones that
once had `talkdem run` flags of their own: older specs name them here)."""
PLANNER_ARGS = {
    "type": "planner",
    "max_steps": "max_steps",
    "scoring": "scoring",
    "feedback": "feedback",
    "thought_tokens": "thought_tokens",
    "log_top": "log_top",
    "clarify": "clarify",
    "clarify_budget": "clarify_budget",
}
"""`planner:` keys and the run setting each sets (`type` is `--planner`)."""
STRATEGY_ALIASES = {
    "care_order": ("order", False),
    "care_dedupe": ("dedupe", False),
    "generation_tokens": ("max_new_tokens", False),
    "generation_plain": ("chat", True),
}
"""Older names of strategy options in a strategy's `args` (the flags they once were): {name: (the strategy's
option, whether a true/false value is inverted)}; `generation_plain: true` is `chat: false`."""

_TOP_KEYS = ("out", "models", "strategies", "conditions", "tasks", "planner", "shards")
_MODEL_KEYS = ("model", "backend", "label", "args", "model_args", "ray")
_STRATEGY_KEYS = ("name", "label", "args")
_RAY_KEYS = ("num_cpus", "num_gpus")
_LABEL = re.compile(r"[A-Za-z0-9][A-Za-z0-9._-]*")
MAX_RUNS = 1_000
"""Runs (models x strategies) a spec may expand into: each is checked by `talkdem run`'s own planning."""
MAX_SHARDS = 10_000
"""Shards per run a spec may ask for (each is a folder and a job; a run has at most 4,800 episodes)."""


class SweepSpecError(ValueError):
    """A spec that cannot be run: the message names the file and the key."""


@dataclass(frozen=True)
class SweepRun:
    """One (model, strategy) of the sweep: a `talkdem run` directory."""

    name: str
    run_dir: Path
    config: RunConfig
    """The run, without `out`, `shard`, `threads` and progress (the executor's)."""
    episode_ids: tuple[str, ...]
    """The run's selection, in its order."""
    model_index: int
    """Which entry of `models` (a Ray actor holds one model, and serves every strategy of it)."""
    resources: Mapping[str, float] = field(default_factory=dict)
    """A Ray actor's resources as the spec gives them (`num_cpus`, `num_gpus`)."""

    @property
    def model(self) -> str:
        return self.config.model

    @property
    def backend(self) -> str:
        return self.config.backend

    @property
    def strategy(self) -> str:
        return self.config.strategy

    @property
    def local_model(self) -> bool:
        return self.backend in LOCAL_BACKENDS

    @property
    def argv(self) -> tuple[str, ...]:
        """`talkdem run` arguments of the run, without the executor's."""
        return tuple(self.config.arguments())

    def job(
        self,
        *,
        out: Path | None = None,
        threads: int | None = None,
        shard: str | None = None,
        continue_on_new_revision: bool = False,
    ) -> RunConfig:
        """The run (or one shard of it) as an executor runs it: into `out`, a local model on `threads` CPU
        threads, without progress lines."""
        model_args = dict(self.config.model_args)
        if threads and self.local_model:
            model_args["threads"] = threads
        return replace(
            self.config,
            model_args=model_args,
            out=out,
            shard=shard,
            continue_on_new_revision=continue_on_new_revision,
            progress=False,
        )

    def command(self, *, out: Path | None = None, threads: int | None = None, shard: str | None = None) -> list[str]:
        """The `talkdem run` arguments of this run (or of one shard of it); `out` None: the caller adds it."""
        return replace(self.job(out=out, threads=threads, shard=shard), progress=True).arguments()


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
        raise _fail(path, key, f"expected a mapping (key: value), got {kind_of(value)}")
    return value


_SHOWN = reprlib.Repr()
_SHOWN.maxstring, _SHOWN.maxother, _SHOWN.maxlist, _SHOWN.maxdict, _SHOWN.maxlevel = 40, 40, 4, 4, 2


def _shown(value: object) -> str:
    """`value` as a message shows it: short, whatever the spec holds (a long string, a big nested list)."""
    return _SHOWN.repr(value)


def _text(path: Path, key: str, value: object) -> str:
    if not isinstance(value, str) or not value.strip():
        raise _fail(path, key, f"expected a non-empty string, got {kind_of(value)}")
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
        raise _fail(path, key, f"expected a non-empty list of {what}, got {kind_of(value)}")
    return value


def _conditions(path: Path, value: object) -> str:
    from talkdem.schema import parse_conditions

    expected = "expected a list of conditions (clean, PATTERN, PATTERN:LEVEL; leave the key out for all 16)"
    items = value.split(",") if isinstance(value, str) else value
    if not isinstance(items, list) or not items:
        raise _fail(path, "conditions", f"{expected}, got {kind_of(value)}")
    for index, item in enumerate(items):
        if not isinstance(item, str):
            raise _fail(path, f"conditions[{index}]", f"expected a condition (a string), got {kind_of(item)}")
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
class _Entry:
    """A model or strategy entry of the spec: its run settings (`RunConfig.from_mapping` keys), where in the spec
    each came from (so a refusal names the spec's key), and its label."""

    index: int
    key: str
    label: str
    values: dict[str, Any]
    where: dict[str, str]
    resources: dict[str, float] = field(default_factory=dict)


def _models(path: Path, value: object) -> list[_Entry]:
    models = []
    for index, entry in enumerate(_list(path, "models", value, "models")):
        key = f"models[{index}]"
        entry = {"model": entry} if isinstance(entry, str) else _mapping(path, key, entry)
        _unknown_keys(path, f"{key}.", entry, _MODEL_KEYS)
        if "model" not in entry:
            raise _fail(path, f"{key}.model", "missing: name the model (`talkdem models`, a file, an id or a name)")
        model = _text(path, f"{key}.model", entry["model"])
        backend = _text(path, f"{key}.backend", entry.get("backend", DEFAULT_BACKEND))
        default_label = Path(model).name.removesuffix(".gguf")
        label = _label(path, f"{key}.label", entry.get("label", default_label))
        values: dict[str, Any] = {"model": model, "backend": backend}
        where = {"model": f"{key}.model", "backend": f"{key}.backend"}
        options = _model_args(path, f"{key}.model_args", backend, entry.get("model_args", {}))
        where.update({f"model_args.{name}": f"{key}.model_args.{name}" for name in options})
        args = _mapping(path, f"{key}.args", entry.get("args", {}))
        _unknown_keys(path, f"{key}.args.", args, list(MODEL_ARGS))
        for name, setting in args.items():
            target = MODEL_ARGS[name]
            if target.startswith("model_args."):
                option = target.removeprefix("model_args.")
                if option in options:
                    raise _fail(path, f"{key}.args.{name}", f"also given as model_args.{option}: give it once")
                options[option] = setting
            else:
                values[target] = setting
            where[target] = f"{key}.args.{name}"
        values["model_args"] = options
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
        models.append(_Entry(index, key, label, values, where, resources))
    return models


def _model_args(path: Path, key: str, backend: str, value: object) -> dict[str, Any]:
    """A model's `model_args` mapping, as the run setting takes it (its values are checked by the backend's
    declaration when the run is built)."""
    options: dict[str, Any] = {}
    for name, setting in _mapping(path, key, value).items():
        where = f"{key}.{name if isinstance(name, str) and len(name) <= 40 else _shown(name)}"
        if not isinstance(name, str) or not name.isidentifier():  # `NAME=VALUE` must split back as it was given
            raise _fail(path, where, f"expected an option name of the {backend} backend, got {kind_of(name)}")
        if name == "threads":
            raise _fail(path, where, "set by the executor (`talkdem sweep --threads`, each worker its share of CPUs)")
        options[name] = setting
    return options


def _strategies(path: Path, value: object) -> list[_Entry]:
    from talkdem.planner.strategies import STRATEGIES

    strategies = []
    for index, entry in enumerate(_list(path, "strategies", value, "strategies")):
        key = f"strategies[{index}]"
        entry = {"name": entry} if isinstance(entry, str) else _mapping(path, key, entry)
        _unknown_keys(path, f"{key}.", entry, _STRATEGY_KEYS)
        if "name" not in entry:
            raise _fail(path, f"{key}.name", f"missing: one of {', '.join(STRATEGIES.names())}")
        name = _text(path, f"{key}.name", entry["name"])
        label = _label(path, f"{key}.label", entry.get("label", name))
        options: dict[str, Any] = {}
        where = {"strategy": f"{key}.name"}
        for option, setting in _mapping(path, f"{key}.args", entry.get("args", {})).items():
            shown = option if isinstance(option, str) and len(option) <= 40 else _shown(option)
            if not isinstance(option, str) or not option.isidentifier():
                raise _fail(path, f"{key}.args.{shown}", f"expected an option name of {name}, got {kind_of(option)}")
            target, inverted = STRATEGY_ALIASES.get(option, (option, False))
            if inverted:
                if not isinstance(setting, bool):
                    raise _fail(path, f"{key}.args.{shown}", f"expected true or false, got {kind_of(setting)}")
                setting = not setting
            if target in options:
                raise _fail(path, f"{key}.args.{shown}", f"given twice (also as {target}): give it once")
            options[target] = setting
            where[f"strategy_args.{target}"] = f"{key}.args.{shown}"
        values = {"strategy": name, "strategy_args": options}
        strategies.append(_Entry(index, key, label, values, where))
    return strategies


def load_sweep(path: Path, out: Path | None = None) -> SweepSpec:
    """Read and validate the spec at `path` (`out`: the output root, instead of the spec's `out`)."""
    from talkdem.runs.plan import plan_run

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
    planner = _mapping(path, "planner", top.get("planner", {}))
    _unknown_keys(path, "planner.", planner, list(PLANNER_ARGS))
    common: dict[str, Any] = {PLANNER_ARGS[name]: setting for name, setting in planner.items()}
    common_where = {PLANNER_ARGS[name]: f"planner.{name}" for name in planner}
    common.update({"conditions": conditions} if conditions else {})
    common.update({"limit": tasks} if tasks else {})
    react = common.get("planner") == "react"
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
    runs: list[SweepRun] = []
    named: dict[str, str] = {}
    for model in models:
        for strategy in strategies:
            name = f"{model.label}{'-react' if react else ''}-{strategy.label}"
            which = f"{model.key} x {strategy.key}"
            if name in named:
                raise _fail(
                    path,
                    which,
                    f"writes {out / name}, as {named[name]} does: give one of them another label",
                )
            named[name] = which
            where = {**common_where, **model.where, **strategy.where}
            try:
                config = RunConfig.from_mapping({**common, **model.values, **strategy.values})
                run = SweepRun(name, out / name, config, (), model.index, model.resources)
                # The run's own checks, as `talkdem run` makes them (threads: as the executor will give them)
                plan = plan_run(run.job(out=run.run_dir, threads=1))
            except RunConfigError as error:
                if error.key in where:
                    raise _fail(path, where[error.key], error.problem) from None
                raise _fail(path, f"{which} ({model.label}, {strategy.label})", str(error)) from None
            except ValueError as error:
                raise _fail(path, f"{which} ({model.label}, {strategy.label})", str(error)) from None
            runs.append(replace(run, episode_ids=tuple(i.id for i in plan.episodes)))
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
