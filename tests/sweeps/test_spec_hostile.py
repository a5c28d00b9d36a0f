"""Hostile sweep specs and `--ray` addresses: each is one line naming the spec (or the address), the field or
line and what was expected, exit 2, never an unexpected exception, a hang or a silently different grid.

The spec's own YAML reader (`talkdem.yaml_input`) refuses alias bombs, deep nesting and duplicate keys while
composing; every field is type-checked at load; the grid and its shards are bounded; an address where nothing
listens is refused before Ray is asked to connect."""

from __future__ import annotations

import copy
import re
import socket
from pathlib import Path
from typing import Any

import pytest
import yaml

from talkdem.cli import main
from talkdem.sweeps.spec import MAX_RUNS, MAX_SHARDS
from talkdem.yaml_input import MAX_CHARS, MAX_DEPTH, MAX_NODES, YamlInputError, load_yaml

BASE: dict[str, Any] = {
    "out": "OUT",
    "models": [
        {
            "model": "smollm2-135m-instruct",
            "backend": "llamacpp",
            "label": "small",
            "args": {"concurrency": 1},
            "model_args": {"n_ctx": 2048},
            "ray": {"num_cpus": 1},
        }
    ],
    "strategies": [
        {"name": "vanilla", "label": "plain", "args": {}},
        {"name": "care", "args": {"care_order": "best_first"}},
    ],
    "conditions": ["clean"],
    "tasks": 1,
    "shards": 1,
    "planner": {"max_steps": 4},
}


def _write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "sweep.yaml"
    path.write_text(text.replace("OUT", str(tmp_path / "out")), encoding="utf-8")
    return path


def _with(field: tuple[str | int, ...], value: object) -> str:
    """BASE with the field at `field` (a path of keys and indexes) set to `value`, as YAML."""
    spec = copy.deepcopy(BASE)
    target: Any = spec
    for step in field[:-1]:
        target = target[step]
    target[field[-1]] = value
    return str(yaml.safe_dump(spec, sort_keys=False))


def _refused(tmp_path: Path, text: str, capsys: pytest.CaptureFixture[str], *extra: str) -> tuple[Path, str]:
    path = _write(tmp_path, text)
    assert main(["sweep", str(path), "--dry-run", *extra]) == 2
    error = capsys.readouterr().err
    assert len(error.strip().splitlines()) == 1, error
    assert "Traceback" not in error and "unexpected" not in error, error
    assert error.startswith(f"talkdem sweep: error: {path}: "), error
    assert not (tmp_path / "out").exists()
    return path, error


def test_the_base_spec_expands(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    # The probes below change one field of this spec: any refusal is that field's.
    assert main(["sweep", str(_write(tmp_path, yaml.safe_dump(BASE, sort_keys=False))), "--dry-run"]) == 0
    assert ": 2 runs, 2 episodes, into " in capsys.readouterr().out


# -- Every field type-checked at load: a list, a mapping or nothing where a scalar belongs, and the reverse.

_TEXT = r"expected a non-empty string, got "


@pytest.mark.parametrize(
    ("field", "value", "where", "expected"),
    [
        # the examples
        (("strategies", 0, "name"), ["vanilla"], "strategies[0].name", _TEXT + "a list"),
        (("models", 0, "backend"), ["openai"], "models[0].backend", _TEXT + "a list"),
        # scalar fields given a list, a mapping, nothing or another type
        (("strategies", 0, "name"), {"a": 1}, "strategies[0].name", _TEXT + "a mapping"),
        (("strategies", 0, "name"), None, "strategies[0].name", _TEXT + "nothing"),
        (("strategies", 0, "name"), 5, "strategies[0].name", _TEXT + "a number"),
        (("strategies", 0, "label"), ["x"], "strategies[0].label", _TEXT + "a list"),
        (("models", 0, "backend"), {"a": 1}, "models[0].backend", _TEXT + "a mapping"),
        (("models", 0, "backend"), None, "models[0].backend", _TEXT + "nothing"),
        (("models", 0, "backend"), 5, "models[0].backend", _TEXT + "a number"),
        (("models", 0, "model"), ["m"], "models[0].model", _TEXT + "a list"),
        (("models", 0, "model"), None, "models[0].model", _TEXT + "nothing"),
        (("models", 0, "label"), {"a": 1}, "models[0].label", _TEXT + "a mapping"),
        (("out",), ["runs"], "out", _TEXT + "a list"),
        (("out",), None, "out", _TEXT + "nothing"),
        (("tasks",), [2], "tasks", r"expected a number of tasks \(at least 1\) or 'all', got \[2\]"),
        (("tasks",), {"n": 2}, "tasks", r"expected a number of tasks .* got \{'n': 2\}"),
        (("tasks",), None, "tasks", r"expected a number of tasks .* got None"),
        (("tasks",), True, "tasks", r"expected a number of tasks .* got True"),
        (("shards",), [2], "shards", rf"expected a whole number from 1 to {MAX_SHARDS:,}, got \[2\]"),
        (("shards",), None, "shards", r"expected a whole number from 1 to .*, got None"),
        (("shards",), 2.5, "shards", r"expected a whole number from 1 to .*, got 2\.5"),
        (("planner", "max_steps"), [4], "planner.max_steps", r"expected a value \(text or a number\), got a list"),
        (("planner", "max_steps"), {"a": 1}, "planner.max_steps", r"expected a value .*, got a mapping"),
        (("planner", "max_steps"), None, "planner.max_steps", r"expected a value .*, got nothing"),
        (("planner", "no_mask_failed"), True, "planner.no_mask_failed", r"unknown key; expected one of type"),
        (("models", 0, "args", "concurrency"), None, "models[0].args.concurrency", r"expected a value .*nothing"),
        (("models", 0, "args", "tokenizer"), {"a": 1}, "models[0].args.tokenizer", r"expected a value .*mapping"),
        (("models", 0, "model_args", "n_ctx"), None, "models[0].model_args.n_ctx", r"expected a value .*nothing"),
        (("models", 0, "model_args", "n_ctx"), {"a": 1}, "models[0].model_args.n_ctx", r"expected a value .*mapping"),
        (
            ("models", 0, "ray", "num_cpus"),
            [1],
            "models[0].ray.num_cpus",
            r"expected a number of at least 0, got \[1\]",
        ),
        (("models", 0, "ray", "num_cpus"), None, "models[0].ray.num_cpus", r"expected a number .*, got None"),
        (("models", 0, "ray", "num_cpus"), "2", "models[0].ray.num_cpus", r"expected a number .*, got '2'"),
        (("models", 0, "ray", "num_cpus"), True, "models[0].ray.num_cpus", r"expected a number .*, got True"),
        (("models", 0, "ray", "num_gpus"), float("nan"), "models[0].ray.num_gpus", r"expected a number .*, got nan"),
        (("strategies", 1, "args", "care_order"), ["best_first"], "strategies[1].args.care_order", r"got a list"),
        # list fields given a scalar, a mapping or nothing; their items of the wrong type
        (("models",), "smollm2-135m-instruct", "models", r"expected a non-empty list of models, got a string"),
        (("models",), {"model": "m"}, "models", r"expected a non-empty list of models, got a mapping"),
        (("models",), None, "models", r"expected a non-empty list of models, got nothing"),
        (("models",), [], "models", r"expected a non-empty list of models, got a list"),
        (("models", 0), 5, "models[0]", r"expected a mapping \(key: value\), got a number"),
        (("models", 0), ["m"], "models[0]", r"expected a mapping \(key: value\), got a list"),
        (("strategies",), "vanilla", "strategies", r"expected a non-empty list of strategies, got a string"),
        (("strategies",), None, "strategies", r"expected a non-empty list of strategies, got nothing"),
        (("strategies", 0), ["vanilla"], "strategies[0]", r"expected a mapping \(key: value\), got a list"),
        (("strategies", 0), None, "strategies[0]", r"expected a mapping \(key: value\), got nothing"),
        (("conditions",), 5, "conditions", r"expected a list of conditions .*, got a number"),
        (("conditions",), {"clean": 1}, "conditions", r"expected a list of conditions .*, got a mapping"),
        (("conditions",), None, "conditions", r"expected a list of conditions .*, got nothing"),
        (
            ("conditions",),
            ["clean", ["intrusion:1"]],
            "conditions[1]",
            r"expected a condition \(a string\), got a list",
        ),
        # nested mappings of the wrong type
        (("planner",), [4], "planner", r"expected a mapping \(key: value\), got a list"),
        (("planner",), None, "planner", r"expected a mapping \(key: value\), got nothing"),
        (("models", 0, "args"), ["concurrency"], "models[0].args", r"expected a mapping \(key: value\), got a list"),
        (("models", 0, "args"), "x", "models[0].args", r"expected a mapping \(key: value\), got a string"),
        (("models", 0, "model_args"), 5, "models[0].model_args", r"expected a mapping \(key: value\), got a number"),
        (("models", 0, "ray"), [1], "models[0].ray", r"expected a mapping \(key: value\), got a list"),
        (("models", 0, "ray"), None, "models[0].ray", r"expected a mapping \(key: value\), got nothing"),
        (("strategies", 1, "args"), ["care_order"], "strategies[1].args", r"expected a mapping \(key: value\)"),
        (("strategies", 1, "args"), None, "strategies[1].args", r"expected a mapping \(key: value\), got nothing"),
    ],
)
def test_a_field_of_the_wrong_type_is_one_line_naming_its_path(
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    field: tuple[str | int, ...],
    value: object,
    where: str,
    expected: str,
) -> None:
    path, error = _refused(tmp_path, _with(field, value), capsys)
    assert f"{path}: {where}: " in error, error
    assert re.search(expected, error), error


@pytest.mark.parametrize(
    ("text", "where", "expected"),
    [
        ("out: 2024-01-01", "out", _TEXT + "a date"),
        ("tasks: 2024-01-01", "tasks", r"expected a number of tasks .*, got datetime\.date"),
        ("tasks: !!set {1, 2}", "tasks", r"expected a number of tasks .*, got \{"),
        ("1: x", "1", r"unknown key; expected one of out, models"),
        ("? !!binary aGk=\n: x", "b'hi'", r"unknown key"),
    ],
)
def test_other_yaml_types_are_refused_by_name(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], text: str, where: str, expected: str
) -> None:
    spec = yaml.safe_dump({k: v for k, v in BASE.items() if k != text.split(":")[0]}, sort_keys=False)
    path, error = _refused(tmp_path, f"{spec}{text}\n", capsys)
    assert f"{path}: {where}: " in error and re.search(expected, error), error


def test_a_strategy_without_a_name_is_missing_one(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path, error = _refused(tmp_path, _with(("strategies", 0), {"label": "x"}), capsys)
    assert f"{path}: strategies[0].name: missing: one of vanilla, ap" in error


def test_a_model_arg_name_that_cannot_be_passed_is_refused(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path, error = _refused(tmp_path, _with(("models", 0, "model_args"), {"n_ctx=1": 5}), capsys)
    assert f"{path}: models[0].model_args.n_ctx=1: expected an option name of the llamacpp backend" in error


# -- Duplicate keys: refused at any depth, naming the key and both lines.


@pytest.mark.parametrize(
    ("text", "line", "key", "first"),
    [
        ("out: OUT\nmodels: [smollm2-135m-instruct]\nstrategies: [vanilla]\ntasks: 1\ntasks: 300\n", 5, "tasks", 4),
        ("out: OUT\nout: elsewhere\nmodels: [smollm2-135m-instruct]\nstrategies: [vanilla]\n", 2, "out", 1),
        (
            "out: OUT\nmodels:\n  - model: smollm2-135m-instruct\n    label: a\n    label: b\nstrategies: [vanilla]\n",
            5,
            "label",
            4,
        ),
        (
            "out: OUT\nmodels: [smollm2-135m-instruct]\nstrategies: [vanilla]\nplanner: {max_steps: 4, max_steps: 5}\n",
            4,
            "max_steps",
            4,
        ),
        (
            "out: OUT\nmodels: [smollm2-135m-instruct]\nstrategies:\n  - {name: care, args: {care_order: best_first,\n"
            "      care_order: best_last}}\n",
            5,
            "care_order",
            4,
        ),
        (
            "out: OUT\nmodels:\n  - model: smollm2-135m-instruct\n    ray:\n      num_cpus: 1\n      num_cpus: 2\n"
            "strategies: [vanilla]\n",
            6,
            "num_cpus",
            5,
        ),
    ],
)
def test_a_duplicate_key_is_refused_naming_it_and_its_lines(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], text: str, line: int, key: str, first: int
) -> None:
    path, error = _refused(tmp_path, text, capsys)
    assert f"{path}: line {line}: duplicate key '{key}' (first on line {first})" in error, error


def test_a_merge_key_may_still_be_overridden(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    # `<<: *base` then one of its keys again is YAML's way of overriding a shared mapping, not a duplicate.
    text = (
        "out: OUT\nmodels:\n  - &base {model: smollm2-135m-instruct, label: a}\n  - {<<: *base, label: b}\n"
        "strategies: [vanilla]\nconditions: [clean]\ntasks: 1\n"
    )
    assert main(["sweep", str(_write(tmp_path, text)), "--dry-run"]) == 0
    printed = capsys.readouterr().out
    assert ": 2 runs, 2 episodes, into " in printed and f"{tmp_path / 'out' / 'b-vanilla'}: " in printed


# -- Resource bombs: refused by the reader before anything expands; the grid and its shards bounded.


def _bomb(field: str, levels: int = 9) -> str:
    """`field:` holding a billion laughs: level k is ten aliases of level k - 1 (10**9 values in all)."""
    lines = [f"{field}:", "  - &l0 [lol, lol, lol, lol, lol, lol, lol, lol, lol, lol]"]
    for level in range(1, levels):
        lines.append(f"  - &l{level} [{', '.join([f'*l{level - 1}'] * 10)}]")
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize("field", ["tasks", "conditions", "shards", "models", "strategies", "planner", "out"])
def test_an_alias_bomb_is_refused_before_it_expands(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], field: str
) -> None:
    spec = {k: v for k, v in BASE.items() if k != field}
    text = yaml.safe_dump(spec, sort_keys=False) + _bomb(field)
    _, error = _refused(tmp_path, text, capsys)
    line = len(text.splitlines()) - 4  # level 4 of 0..8: 111,111 values, the first past the bound
    assert f": line {line}: expands into more than {MAX_NODES:,} values" in error, error


def test_a_shared_mapping_by_alias_is_still_read(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    text = (
        "out: OUT\nmodels:\n  - {model: smollm2-135m-instruct, label: a, model_args: &args {n_ctx: 2048}}\n"
        "  - {model: smollm2-135m-instruct, label: b, model_args: *args}\nstrategies: [vanilla]\n"
        "conditions: [clean]\ntasks: 1\n"
    )
    path = _write(tmp_path, text)
    assert main(["sweep", str(path), "--dry-run"]) == 0
    assert ": 2 runs, 2 episodes, into " in capsys.readouterr().out


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("tasks: " + "[" * (MAX_DEPTH + 10) + "1" + "]" * (MAX_DEPTH + 10), rf"line 1: nested deeper than {MAX_DEPTH}"),
        ("tasks: " + "[" * 100_000, rf"line 1: nested deeper than {MAX_DEPTH}"),
        ("tasks: &a [*a]", r"line 1: an alias refers to a collection that contains it"),
        ("tasks: " + "9" * 5000, r"line 1: cannot read '9999.*\.\.\.': Exceeds the limit"),
        ("out: 2024-02-30", r"line 1: cannot read '2024-02-30': day is out of range for month"),
        ("tasks: 1\n---\ntasks: 2", r"line 2: not valid YAML \(expected a single document"),
    ],
)
def test_nesting_recursion_and_unbuildable_values_are_refused_by_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], text: str, expected: str
) -> None:
    _, error = _refused(tmp_path, text + "\n", capsys)
    assert re.search(expected, error), error


def test_a_spec_file_past_the_bound_is_not_read_whole(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path, error = _refused(tmp_path, "# " + "x" * MAX_CHARS + "\n", capsys)
    assert f"{path}: larger than {MAX_CHARS:,} bytes" in error


def test_a_grid_past_the_bound_is_refused_before_its_runs_are_planned(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    models = [{"model": "smollm2-135m-instruct", "label": f"m{i}"} for i in range(MAX_RUNS // 5 + 1)]
    spec = {**BASE, "models": models, "strategies": ["vanilla", "ap", "cot", "icl", "tocc"]}
    path, error = _refused(tmp_path, yaml.safe_dump(spec), capsys)
    runs = len(models) * 5
    assert f"{path}: models x strategies: {runs:,} runs; a spec expands into at most {MAX_RUNS:,}" in error


@pytest.mark.parametrize("shards", [MAX_SHARDS + 1, 10**30, 0])
def test_shards_past_the_bound_are_refused(tmp_path: Path, capsys: pytest.CaptureFixture[str], shards: int) -> None:
    path, error = _refused(tmp_path, _with(("shards",), shards), capsys)
    assert f"{path}: shards: expected a whole number from 1 to {MAX_SHARDS:,}" in error


def test_the_reader_names_lines_for_its_other_users() -> None:
    # The dataset card's front matter goes through the same reader (talkdem.instructions).
    with pytest.raises(YamlInputError) as refused:
        load_yaml("configs:\n- config_name: a\n  config_name: b\n")
    assert refused.value.line == 3 and not refused.value.syntax
    assert "duplicate key 'config_name' (first on line 2)" in refused.value.problem
    with pytest.raises(YamlInputError) as refused:
        load_yaml("a: [1\n")
    assert refused.value.syntax and refused.value.line == 2


def test_a_dataset_card_with_a_duplicate_key_names_the_file_and_line(tmp_path: Path) -> None:
    from talkdem.instructions import dataset_configs

    (tmp_path / "README.md").write_text("---\nconfigs:\n- config_name: a\n  config_name: b\n---\n", encoding="utf-8")
    with pytest.raises(
        ValueError, match=re.escape(f"{tmp_path / 'README.md'}:4: the card's YAML front matter is refused")
    ):
        dataset_configs.__wrapped__(tmp_path)


# -- `--ray ADDRESS` where nothing listens: refused at once, naming the address (Ray is never asked).


def _closed_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as probe:
        probe.bind(("127.0.0.1", 0))
        return int(probe.getsockname()[1])


def _ray_refused(tmp_path: Path, capsys: pytest.CaptureFixture[str], address: str) -> str:
    path = _write(tmp_path, yaml.safe_dump(BASE, sort_keys=False))
    assert main(["sweep", str(path), "--ray", address, "--no-progress"]) == 2
    error = capsys.readouterr().err
    assert len(error.strip().splitlines()) == 1 and "Traceback" not in error and "unexpected" not in error, error
    assert not (tmp_path / "out").exists()
    return error


@pytest.mark.parametrize("scheme", ["", "ray://"])
def test_a_ray_address_where_nothing_listens_is_one_line_naming_it(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], scheme: str
) -> None:
    port = _closed_port()
    address = f"{scheme}127.0.0.1:{port}"
    error = _ray_refused(tmp_path, capsys, address)
    assert f"talkdem sweep: error: --ray {address}: no Ray cluster at 127.0.0.1:{port} (" in error, error


def test_ray_auto_checks_the_address_ray_address_names(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    port = _closed_port()
    monkeypatch.setenv("RAY_ADDRESS", f"127.0.0.1:{port}")
    error = _ray_refused(tmp_path, capsys, "auto")
    assert f"--ray auto (RAY_ADDRESS=127.0.0.1:{port}): no Ray cluster at 127.0.0.1:{port}" in error, error


@pytest.mark.parametrize("address", ["nowhere", "127.0.0.1:port", "127.0.0.1:70000", ":6379"])
def test_a_malformed_ray_address_is_refused(tmp_path: Path, capsys: pytest.CaptureFixture[str], address: str) -> None:
    error = _ray_refused(tmp_path, capsys, address)
    assert f"--ray {address}: expected auto, HOST:PORT or ray://HOST:PORT" in error, error
