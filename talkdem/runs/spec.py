"""The run spec: everything that decides what a run's episodes mean, in one typed value.

A `RunSpec` holds the planner settings (every field of `SayCanConfig`, taken generically so that a setting
added there is recorded and compared without an edit here), the strategy and its arguments, the backend's
arguments, the episode selection, and the SHA-256 of every input file the run reads. It writes the run
header, and the keys that a resume and a merge compare are derived from it: a resume after any input file
changed, or with another planner setting, is refused, since its episodes could not be pooled.

Headers written before input files were hashed have no `inputs`: those are *unknown*, never made up; a
resume says so (`RunSpecWarning`) and goes on, as it did then.
"""

from __future__ import annotations

import dataclasses
import hashlib
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from talkdem.planner.react import ReActConfig
from talkdem.planner.saycan import SayCanConfig
from talkdem.runs.records import RunHeader

if TYPE_CHECKING:
    from talkdem.planner.strategies import Strategy

__all__ = [
    "MERGE_KEYS",
    "OUTCOME_KEYS",
    "RESUME_KEYS",
    "RunSpec",
    "RunSpecWarning",
    "Scalar",
    "Setting",
    "check_same_run",
    "clarify_generator",
    "differences",
    "header_value",
    "input_files",
    "input_hashes",
    "planner_settings",
    "strategy_arguments",
]

Scalar = str | int | float | bool
Setting = Scalar | list[Scalar]
"""A strategy argument: a plain value, or a list of them (CoT and TOCC's stop strings)."""

NOT_OUTCOME = frozenset({"log_top"})
"""`SayCanConfig` fields that change what is logged, not which plan is chosen: recorded, never compared.
Every other field (including any added later) changes what an outcome means."""

_PROMPTS = Path(__file__).resolve().parent.parent / "planner" / "prompts"
_PROMPTS_LABEL = "talkdem/planner/prompts"


class RunSpecWarning(UserWarning):
    """A resume that cannot check everything (a header written before a field existed)."""


PlannerConfig = SayCanConfig | ReActConfig
"""The planners `talkdem run` drives (SayCan's scoring and generative modes, ReAct)."""


def planner_settings(config: PlannerConfig) -> dict[str, Scalar]:
    """Every field of the planner configuration, by name."""
    return {f.name: getattr(config, f.name) for f in dataclasses.fields(config)}


def _outcome_keys() -> tuple[str, ...]:
    # Every planner's fields: a setting one planner lacks is absent from both headers, hence not compared.
    names = list(dict.fromkeys(f.name for c in (SayCanConfig, ReActConfig) for f in dataclasses.fields(c)))
    planner = tuple(f"config.{name}" for name in names if name not in NOT_OUTCOME)
    return (
        "model",
        "planner",
        "strategy",
        "prompt_version",
        "dataset_hash",
        *planner,
        "config.strategy_args",
        "config.clarify_generator",
        "inputs",
    )


OUTCOME_KEYS = _outcome_keys()
"""Header fields (top level, or `config.NAME`) that change what an episode's outcome means: episodes that
differ in any of them cannot be pooled into one run (resume and merge both check them)."""

RESUME_KEYS = (*OUTCOME_KEYS, "config.shard")
"""A resume also keeps a shard's folder to its shard (the selection may grow between sittings)."""

MERGE_KEYS = (*OUTCOME_KEYS, "config.conditions", "config.limit")
"""Every shard of one run agrees on what an outcome means and on which episodes the run covers."""


def _setting(value: object) -> Setting | None:
    """`value` as the header records it (tuples as lists), or None when it is no plain setting."""
    if isinstance(value, str | int | float | bool):
        return value
    if isinstance(value, list | tuple) and all(isinstance(v, str | int | float | bool) for v in value):
        return list(value)
    return None


def strategy_arguments(strategy: Strategy) -> dict[str, Setting]:
    """A strategy's settings: what its `options()` says, where it has that method, else its public
    attributes that are plain values (CARE's `k`). Data it holds (the memory bank, demonstrations, an
    encoder) is not an argument; the files it came from are inputs."""
    options = getattr(strategy, "options", None)
    if callable(options):
        declared = options()
        if isinstance(declared, Mapping):
            return {str(k): setting for k, v in sorted(declared.items()) if (setting := _setting(v)) is not None}
    return {
        name: value
        for name, value in sorted(vars(strategy).items())
        if not name.startswith("_") and name != "name" and isinstance(value, str | int | float | bool)
    }


def input_files(*, planner: bool = True) -> dict[str, Path]:
    """Every file a run reads, by the name the header records (`data/...` for the dataset folder, whatever
    its place on this machine, so a header names no machine path).

    Every run: the task records (`tasks/*.jsonl`: the simulator's initial states and goals) and the
    dataset's declared Parquet files (instructions, memory bank). A planner run (`planner=True`) also reads
    the worked examples (`prompts/saycan_examples.jsonl`) and the prompt templates."""
    from talkdem.instructions import dataset_configs
    from talkdem.paths import data_dir
    from talkdem.planner.examples import examples_file
    from talkdem.tasks import TaskSet, task_file

    root = data_dir()
    files: dict[str, Path] = {}

    def add(path: Path) -> None:
        files[f"data/{path.relative_to(root).as_posix()}"] = path

    # The folder is passed on explicitly: the readers cache by argument, and `$TALKDEM_DATA_DIR` may have
    # changed since a call without one.
    for task_set in TaskSet:
        add(task_file(task_set, root))
    for splits in dataset_configs(root).values():
        for paths in splits.values():
            for path in paths:
                add(path)
    if planner:
        add(examples_file(root))
        for path in sorted(_PROMPTS.iterdir()):
            if path.is_file():
                files[f"{_PROMPTS_LABEL}/{path.name}"] = path
    return dict(sorted(files.items()))


def _sha256(path: Path) -> str:
    digest = hashlib.sha256()
    try:
        with path.open("rb") as handle:
            for block in iter(lambda: handle.read(1 << 20), b""):
                digest.update(block)
    except FileNotFoundError:
        raise FileNotFoundError(f"{path}: an input file of the run is missing") from None
    return digest.hexdigest()


def input_hashes(*, planner: bool = True) -> dict[str, str]:
    """`{name: sha256}` of every file of `input_files`."""
    return {name: _sha256(path) for name, path in input_files(planner=planner).items()}


@dataclass(frozen=True)
class RunSpec:
    """One planner run, fully specified."""

    planner: PlannerConfig
    strategy: str
    strategy_args: dict[str, Setting] = field(default_factory=dict)
    backend_args: dict[str, Scalar] = field(default_factory=dict)
    """How the model was reached (backend, threads, timeout, tokenizer name, ...): recorded, not compared (a
    sitting on another thread count or server may resume a run)."""
    selection: dict[str, Any] = field(default_factory=dict)
    """Conditions, sample size, shard, and what else the caller records (`talkdem run`'s `--threads`)."""
    inputs: dict[str, str] = field(default_factory=dict)

    @classmethod
    def for_run(
        cls,
        config: PlannerConfig,
        strategy: Strategy,
        *,
        backend_args: Mapping[str, Scalar] | None = None,
        selection: Mapping[str, Any] | None = None,
    ) -> RunSpec:
        """The spec of a run starting now: the input files are hashed as they are on disk."""
        return cls(
            planner=config,
            strategy=strategy.name,
            strategy_args=strategy_arguments(strategy),
            backend_args=dict(backend_args or {}),
            selection=dict(selection or {}),
            inputs=input_hashes(),
        )

    @property
    def max_steps(self) -> int:
        return self.planner.max_steps

    @property
    def resume_keys(self) -> tuple[str, ...]:
        return RESUME_KEYS

    @property
    def merge_keys(self) -> tuple[str, ...]:
        return MERGE_KEYS

    def header(
        self,
        *,
        model: dict[str, str],
        planned_episodes: int,
        served: Mapping[str, object] | None = None,
        runtime: dict[str, str] | None = None,
    ) -> RunHeader:
        """The header of this run (status `running`, the current code revision and dataset hash; `runtime`:
        this sitting's, when the model runs in this process)."""
        from talkdem.planner.prompt import prompt_version
        from talkdem.planner.react import react_prompt_version

        clarify = self.planner.clarify
        if isinstance(self.planner, ReActConfig):
            version = react_prompt_version(clarify, self.planner.clarify_budget)
            feedback: dict[str, Any] = {}
        else:
            # What a run sets that changes a rendered prompt names the prompt version too (clarification only
            # when on: a run without it keeps the version it always had).
            settings: dict[str, object] = {
                "failure_message": self.planner.failure_message,
                "strategy_args": dict(self.strategy_args),
            }
            if clarify != "none":
                settings["clarify_budget"] = self.planner.clarify_budget
            version = prompt_version(settings)
            feedback = {"feedback": self.planner.feedback}
        if clarify == "in-pattern":
            # The answers' wording comes from the dataset generator: its name and phrase-bank version decide
            # what an in-pattern outcome means (compared on resume and merge).
            feedback["clarify_generator"] = clarify_generator()
        config: dict[str, Any] = {
            **planner_settings(self.planner),
            **feedback,
            "strategy_args": dict(self.strategy_args),
            "backend_args": dict(self.backend_args),
            **self.selection,
            **({"served": dict(served)} if served else {}),
            "planned_episodes": planned_episodes,
        }
        return RunHeader.new(
            model=model,
            planner=self.planner.planner_name,
            strategy=self.strategy,
            prompt_version=version,
            config=config,
            inputs=self.inputs,
            runtime=runtime,
        )


def clarify_generator() -> str:
    """`<generator name>/<its prompt version>` of the generator that speaks in-pattern answers."""
    from talkdem.clarify.person import GENERATOR
    from talkdem.speech import get_generator

    return f"{GENERATOR}/{get_generator(GENERATOR).prompt_version}"


_UNKNOWN = object()
_BEFORE_CLARIFICATION = {"clarify": "none", "clarify_budget": 0}
"""Settings whose value in a header written before they existed is known: no run asked questions then."""


def header_value(header: RunHeader, key: str) -> Any:
    """A key's value (`NAME` top level or `config.NAME`); a field the header predates is unknown
    (`_UNKNOWN`), never today's default: a setting added later may have a default that differs from how
    older code behaved. (No shard, conditions or limit recorded means none.)"""
    if key.startswith("config."):
        name = key.removeprefix("config.")
        if name in header.config:
            return header.config[name]
        if name in _BEFORE_CLARIFICATION:
            return _BEFORE_CLARIFICATION[name]
        return None if name in ("shard", "conditions", "limit") else _UNKNOWN
    if key == "inputs":
        return header.inputs or _UNKNOWN
    return header.to_json()[key]


def _short(digest: str) -> str:
    return digest[:12] if digest else "none"


def _input_changes(existing: Mapping[str, str], wanted: Mapping[str, str]) -> list[str]:
    changes = []
    for name in sorted(set(existing) | set(wanted)):
        before, after = existing.get(name, ""), wanted.get(name, "")
        if before == after:
            continue
        if not before:
            changes.append(f"{name} is read now but was not when the run started")
        elif not after:
            changes.append(f"{name} was read when the run started but is not now")
        else:
            changes.append(f"{name} changed since the run started (sha256 {_short(before)}... -> {_short(after)}...)")
    return changes


def check_same_run(run_dir: Path, existing: RunHeader, wanted: RunHeader, keys: Sequence[str]) -> None:
    """Refuse to pool `wanted`'s episodes into the run `existing` describes unless every key agrees; a key
    the existing header predates is unknown: named in one `RunSpecWarning`, not compared."""
    clashes, unknown = [], []
    for key in keys:
        before, after = header_value(existing, key), header_value(wanted, key)
        if before is _UNKNOWN:
            if after is not _UNKNOWN:
                unknown.append(key)
            continue
        if key == "inputs":
            changes = _input_changes(before, {} if after is _UNKNOWN else after)
            if changes:
                raise ValueError(
                    f"{run_dir}: {'; '.join(changes)}; its episodes and new ones could not be pooled: restore the "
                    "file or choose another --out"
                )
            continue
        if before != after:
            shown = "unknown" if after is _UNKNOWN else repr(after)
            clashes.append(f"{key}: {before!r} there, {shown} now")
    if clashes:
        raise ValueError(f"{run_dir} holds a different run ({'; '.join(clashes)}); choose another --out")
    if unknown:
        what = "input file hashes" if "inputs" in unknown else ", ".join(unknown)
        others = [k for k in unknown if k != "inputs"]
        also = f" (nor {', '.join(others)})" if others and "inputs" in unknown else ""
        warnings.warn(
            f"{run_dir}: its header records no {what}{also} (written by an older version): whether they changed "
            "since the run started is unknown; resuming anyway",
            RunSpecWarning,
            stacklevel=3,
        )


def differences(first: RunHeader, other: RunHeader, keys: Sequence[str]) -> list[str]:
    """`key: A vs B` for every key on which two headers disagree (shards of one run must not): a field one
    header predates is `unknown` there, and differs from a recorded one."""
    found = []
    for key in keys:
        a, b = header_value(first, key), header_value(other, key)
        if a == b:
            continue
        if key == "inputs" and a is not _UNKNOWN and b is not _UNKNOWN:
            found.append(
                "; ".join(c.replace("since the run started", "between the shards") for c in _input_changes(a, b))
            )
            continue
        shown = ["unknown" if v is _UNKNOWN else repr(v) for v in (a, b)]
        found.append(f"{key}: {shown[0]} vs {shown[1]}")
    return found
