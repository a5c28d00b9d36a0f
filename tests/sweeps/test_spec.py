"""The sweep spec: every mistake is one line naming the file, the key and what was expected (exit 2, no
traceback); the dry run prints the expansion and writes nothing; the example specs expand as docs/serving.md says."""

from __future__ import annotations

import re
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest
import yaml

from talkdem.cli import main
from talkdem.paths import repo_root
from talkdem.sweeps import load_sweep

GOOD = """\
out: OUT
models:
  - smollm2-135m-instruct
  - model: served-7b
    backend: openai
    label: s7
    args: {base_url: [http://127.0.0.1:9/v1, http://127.0.0.1:8/v1], tokenizer: smollm2-135m-instruct, concurrency: 2}
strategies: [vanilla, {name: care, args: {care_order: best_first}}]
conditions: [clean, intrusion:1]
tasks: 2
planner: {max_steps: 4}
"""


def _spec(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "sweep.yaml"
    path.write_text(text.replace("OUT", str(tmp_path / "out")))
    return path


def _refused(tmp_path: Path, text: str, capsys: pytest.CaptureFixture[str]) -> str:
    path = _spec(tmp_path, text)
    assert main(["sweep", str(path), "--dry-run"]) == 2
    error = capsys.readouterr().err
    assert len(error.strip().splitlines()) == 1 and "Traceback" not in error, error
    assert str(path) in error
    return error


@pytest.mark.parametrize(
    ("change", "expected"),
    [
        (("tasks: 2", "tasks: 0"), r"tasks: expected a number of tasks \(at least 1\) or 'all', got 0"),
        (("tasks: 2", "taks: 2"), r"taks: unknown key \(did you mean 'tasks'\?\)"),
        (("intrusion:1", "intrusion:7"), r"conditions: condition 'intrusion:7': the level must be 1, 2 or 3"),
        (("[vanilla,", "[vanila,"), r"strategies\[0\]\.name: expected one of .* \(did you mean 'vanilla'\?\)"),
        (("max_steps: 4", "max_steps: -1"), r"planner\.max_steps: must be at least 1, got -1"),
        (("max_steps: 4", "max_steps: many"), r"planner\.max_steps: 'many' is not a whole number"),
        (("max_steps: 4", "feedback: loud"), r"planner\.feedback: invalid choice: 'loud'"),
        (("concurrency: 2", "concurrency: 1"), r"models\[1\] x strategies\[0\] \(s7, vanilla\): 2 --base-url"),
        (
            ("care_order: best_first", "care_order: best_first, generation_plain: 1"),
            r"generation_plain: expected true or false",
        ),
        (("backend: openai", "backend: gpt"), r"models\[1\]\.backend: expected one of"),
        (("{name: care, args:", "{name: care, label: vanilla, args:"), r"writes .*vanilla, as models\[0\] x "),
        (("out: OUT\n", ""), r"out: missing"),
        (("planner: {max_steps: 4}", "planner: [4]"), r"planner: expected a mapping"),
        (("tasks: 2", "tasks: [2"), r"line \d+: not valid YAML"),
    ],
)
def test_a_bad_spec_is_one_line_naming_the_key(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], change: tuple[str, str], expected: str
) -> None:
    assert change[0] in GOOD
    error = _refused(tmp_path, GOOD.replace(*change), capsys)
    assert re.search(expected, error), error


MODEL_ARGS = "  - smollm2-135m-instruct\n"


@pytest.mark.parametrize(
    ("model_args", "expected"),
    [
        ("{n_ctx: 0}", r"models\[0\]\.model_args\.n_ctx: model arg n_ctx='0': the llamacpp backend's 'n_ctx' takes"),
        ("{tokenizer: x}", r"models\[0\]\.model_args\.tokenizer: .*the llamacpp backend has no such option"),
        ("{threads: 2}", r"models\[0\]\.model_args\.threads: set by the executor"),
        (
            "{n_ctx: [1]}",
            r"models\[0\]\.model_args\.n_ctx: expected a value \(text, a number or true/false\), got a list",
        ),
        ("[n_ctx]", r"models\[0\]\.model_args: expected a mapping"),
    ],
)
def test_a_bad_model_arg_names_its_key(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], model_args: str, expected: str
) -> None:
    text = GOOD.replace(MODEL_ARGS, f"  - model: smollm2-135m-instruct\n    model_args: {model_args}\n")
    assert re.search(expected, _refused(tmp_path, text, capsys))


def test_model_args_reach_the_run_as_the_backend_parsed_them(tmp_path: Path) -> None:
    text = GOOD.replace(
        MODEL_ARGS, "  - model: smollm2-135m-instruct\n    model_args: {n_ctx: 2048, f32_kv_cache: false}\n"
    )
    text = text.replace("concurrency: 2}", "concurrency: 2}\n    model_args: {timeout: 120, endpoint: auto}")
    spec = load_sweep(_spec(tmp_path, text))
    assert spec.runs[0].config.model_args == {"n_ctx": 2048, "f32_kv_cache": False}
    assert spec.runs[0].argv[4:8] == ("--model-arg", "n_ctx=2048", "--model-arg", "f32_kv_cache=false")
    # the older `args` spelling of a backend option and `model_args` are one mapping
    assert spec.runs[2].config.model_args == {
        "tokenizer": "smollm2-135m-instruct",
        "timeout": 120.0,
        "endpoint": "auto",
    }
    assert "timeout=120.0" in spec.runs[2].argv and "endpoint=auto" in spec.runs[2].argv


def test_a_backend_option_given_twice_is_refused(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    text = GOOD.replace("concurrency: 2}", "concurrency: 2}\n    model_args: {tokenizer: other}")
    error = _refused(tmp_path, text, capsys)
    assert "models[1].args.tokenizer: also given as model_args.tokenizer: give it once" in error


@pytest.mark.parametrize(
    ("older", "newer"),
    [
        (
            "{name: care, args: {care_order: best_first, care_dedupe: true}}",
            "{name: care, args: {order: best_first, dedupe: true}}",
        ),
        (
            "{name: cot, args: {generation_tokens: 64, generation_plain: true}}",
            "{name: cot, args: {max_new_tokens: 64, chat: false}}",
        ),
        ("{name: tocc, args: {generation_plain: false}}", "{name: tocc, args: {chat: true}}"),
    ],
)
def test_a_strategys_options_by_their_older_names_are_the_same_run(tmp_path: Path, older: str, newer: str) -> None:
    def config(entry: str) -> object:
        text = GOOD.replace("[vanilla, {name: care, args: {care_order: best_first}}]", f"[{entry}]")
        return load_sweep(_spec(tmp_path, text)).runs[0].config

    assert config(older) == config(newer)


def test_a_strategy_option_is_checked_by_the_strategy(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    text = GOOD.replace("care_order: best_first", "order: worst_first")
    error = _refused(tmp_path, text, capsys)
    assert (
        "strategies[1].args.order: strategy arg order='worst_first': the care strategy's 'order' takes one of" in error
    )
    text = GOOD.replace("care_order: best_first", "k: 5")
    error = _refused(tmp_path, text, capsys)
    assert (
        "strategies[1].args.k: strategy arg 'k': the care strategy has no such option (its options: order, dedupe)"
        in error
    )


def test_a_strategy_flag_of_another_strategy_is_refused(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    error = _refused(tmp_path, GOOD.replace("[vanilla,", "[{name: vanilla, args: {care_dedupe: true}},"), capsys)
    assert "strategies[0].args.care_dedupe: strategy arg 'dedupe': the vanilla strategy has no such option" in error
    assert error.rstrip().endswith("; care has it")


def test_a_missing_spec_file(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["sweep", str(tmp_path / "none.yaml"), "--dry-run"]) == 2
    assert "none.yaml: no such spec file" in capsys.readouterr().err


def test_the_dry_run_prints_every_run_and_writes_nothing(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = _spec(tmp_path, GOOD)
    assert main(["sweep", str(path), "--dry-run", "--workers", "2"]) == 0
    printed = capsys.readouterr().out
    spec = load_sweep(path)
    assert [r.name for r in spec.runs] == [
        "smollm2-135m-instruct-vanilla",
        "smollm2-135m-instruct-care",
        "s7-vanilla",
        "s7-care",
    ]
    assert all(len(r.episode_ids) == 4 for r in spec.runs)  # 2 tasks x 2 conditions
    assert printed.splitlines()[0].endswith(f"4 runs, 16 episodes, into {tmp_path / 'out'}")
    for run in spec.runs:
        line = f"{run.run_dir}: {run.backend} {run.model}, {run.strategy}, 4 episodes (0 on disk), 2 shard(s)"
        assert line in printed
    commands = [line.strip() for line in printed.splitlines() if line.strip().startswith("talkdem run ")]
    assert len(commands) == 4
    assert "--model-arg threads=" in commands[0] and "threads=" not in commands[2]  # a served model computes elsewhere
    assert "--base-url http://127.0.0.1:9/v1 --base-url http://127.0.0.1:8/v1" in commands[2]
    assert "--strategy-arg order=best_first" in commands[1] and "--max-steps 4" in commands[0]
    assert not (tmp_path / "out").exists()


def _readme_section() -> str:
    """The "Sweeps" section of docs/serving.md (it was the README's)."""
    text = (repo_root() / "docs" / "serving.md").read_text(encoding="utf-8")
    start = text.index("\n## Sweeps\n")
    return text[start : text.find("\n## ", start + 1)]


def test_the_example_specs_expand_as_the_docs_say(capsys: pytest.CaptureFixture[str]) -> None:
    section = _readme_section()
    named = sorted(set(re.findall(r"examples/[\w.-]+\.yaml", section)))
    assert named == ["examples/sweep-paper.yaml", "examples/sweep-smoke.yaml"]
    for name in named:
        assert main(["sweep", str(repo_root() / name), "--dry-run"]) == 0
        first = capsys.readouterr().out.splitlines()[0]
        runs, episodes = re.search(r": (\d+) runs, (\d+) episodes", first).groups()  # type: ignore[union-attr]
        claim = re.search(rf"`{re.escape(name)}`[^\n]*?(\d+) runs, ([\d,]+) episodes", section)
        assert claim is not None, f"docs/serving.md says nothing of {name}'s size"
        assert (claim.group(1), claim.group(2).replace(",", "")) == (runs, episodes)
    (shown,) = re.findall(r"```yaml\n(# examples/sweep-smoke.yaml\n.*?)```", section, flags=re.DOTALL)
    assert yaml.safe_load(shown) == yaml.safe_load((repo_root() / "examples" / "sweep-smoke.yaml").read_text())


def test_the_dry_run_imports_no_heavy_library_nor_ray() -> None:
    code = (
        "import sys\n"
        "from talkdem.cli import main\n"
        f"main(['sweep', {str(repo_root() / 'examples' / 'sweep-paper.yaml')!r}, '--dry-run'])\n"
        "heavy = [m for m in ('torch', 'transformers', 'sentence_transformers', 'llama_cpp', 'ray')\n"
        "         if m in sys.modules]\n"
        "print('HEAVY', heavy, file=sys.stderr)\n"
    )
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert "HEAVY []" in result.stderr


def test_a_sweep_builds_and_checks_its_runs_without_the_cli() -> None:
    # The sweep's runs are run configurations, planned and compared without `talkdem run`'s parser.
    code = (
        "import sys\n"
        "from pathlib import Path\n"
        "from talkdem.sweeps import load_sweep\n"
        "from talkdem.sweeps.work import wanted_header\n"
        f"spec = load_sweep(Path({str(repo_root() / 'results' / 'paper' / 'sweep.yaml')!r}))\n"
        "header = wanted_header(spec.runs[0])\n"
        "print('RUNS', len(spec.runs), header.strategy, file=sys.stderr)\n"
        "print('CLI', sorted(m for m in sys.modules if m == 'talkdem.cli' or m.startswith('talkdem.cli.')), "
        "file=sys.stderr)\n"
    )
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert "RUNS 6 vanilla" in result.stderr and "CLI []" in result.stderr, result.stderr


def test_ray_missing_is_one_line_naming_the_extra(tmp_path: Path) -> None:
    # A `ray` that cannot be imported (None in sys.modules), as on an install without the extra.
    code = (
        "import sys\n"
        "sys.modules['ray'] = None\n"
        "from talkdem.cli import main\n"
        f"sys.exit(main(['sweep', {str(_spec(tmp_path, GOOD))!r}, '--ray', 'auto']))\n"
    )
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=False)
    assert result.returncode == 2 and len(result.stderr.strip().splitlines()) == 1
    assert "Ray is not installed (the optional extra `ray`)" in result.stderr
    (requirement,) = tomllib.loads((repo_root() / "pyproject.toml").read_text())["project"]["optional-dependencies"][
        "ray"
    ]
    assert f"pip install '{requirement}'" in result.stderr and "pip install -e '.[ray]'" in result.stderr
    assert not (tmp_path / "out").exists()


def test_only_keeps_the_named_runs_in_the_same_directories(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = _spec(tmp_path, GOOD)
    whole = {run.name: run for run in load_sweep(path).runs}
    assert main(["sweep", str(path), "--dry-run", "--only", "s7-care,smollm2-135m-instruct-vanilla"]) == 0
    printed = capsys.readouterr().out
    assert printed.splitlines()[0].endswith(f"2 runs, 8 episodes, into {tmp_path / 'out'}")
    listed = [line.split(":")[0].strip() for line in printed.splitlines()[1:] if not line.startswith("    ")]
    # the spec's order and the whole grid's folders, not the order given
    assert listed == [str(whole["smollm2-135m-instruct-vanilla"].run_dir), str(whole["s7-care"].run_dir)]


def test_only_refuses_a_name_the_spec_does_not_have(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = _spec(tmp_path, GOOD)
    assert main(["sweep", str(path), "--dry-run", "--only", "s7-cares"]) == 2
    error = capsys.readouterr().err
    assert len(error.strip().splitlines()) == 1 and "Traceback" not in error, error
    assert f"{path}: no run named 's7-cares' (did you mean 's7-care'?)" in error
