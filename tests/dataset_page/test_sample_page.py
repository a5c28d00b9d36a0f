"""The sample page on the shipped data and on a tiny dataset of hostile text: what it holds, what it escapes,
what it never names (a machine path, a network address), and the command's errors."""

from __future__ import annotations

import html
import json
import re
import shutil
from pathlib import Path

import pytest
from tiny_dataset import TinyTask, write_tiny_dataset

from talkdem.cli import main
from talkdem.dataset_page import load_page_tasks, render_sample_page, sample_tasks, write_sample_page
from talkdem.paths import repo_root
from talkdem.schema import CLEAN, TASK_TYPES

DATA = repo_root() / "data"
HOSTILE = '<script>window.pwned = 1</script>"><img src=x onerror="window.pwned = 2">&amp;'


def _tiny_task(n: int, task_type: str, hostile: bool = False) -> TinyTask:
    extra = f" {HOSTILE}" if hostile else ""

    def text(pattern: str, level: int) -> str:
        clean = f"Hello, put the apple{extra} on the shelf, please."
        return clean if pattern == CLEAN else clean.replace("the apple", f"the, um, {pattern} {level} apple")

    return TinyTask(
        f"trial_{n:02d}",
        task_type,
        "Apple",
        f"{task_type}-Apple-None-Shelf-{n}",
        text,
        seed=f"Put the apple on the shelf.{extra}",
        failed=frozenset({("intrusion", 3)}) if hostile else frozenset(),
    )


@pytest.fixture(scope="module")
def tiny(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Seven tasks of two types; trial_03 carries markup in its seed, clean control and every variant."""
    tasks = [_tiny_task(n, TASK_TYPES[n % 2], hostile=n == 3) for n in range(7)]
    return write_tiny_dataset(tmp_path_factory.mktemp("tiny") / "data", tasks, tasks[:1])


@pytest.fixture(scope="module")
def shipped_page(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("page") / "sample.html"
    assert main(["sample-page", str(DATA), "--out", str(out)]) == 0
    return out


def test_the_sample_is_spread_over_each_type(tiny: Path) -> None:
    tasks = load_page_tasks(tiny)
    assert [t.task_id for t in tasks] == [f"trial_{n:02d}" for n in range(7)]
    # Type 0 has trials 0, 2, 4, 6; type 1 has 1, 3, 5: two of each, from the middle of each half.
    assert [t.task_id for t in sample_tasks(tasks, 2)] == ["trial_02", "trial_06", "trial_01", "trial_05"]
    assert len(sample_tasks(tasks, None)) == len(sample_tasks(tasks, 10)) == 7
    with pytest.raises(ValueError, match="at least 1"):
        sample_tasks(tasks, 0)


def test_the_shipped_page_shows_five_tasks_per_type_with_all_variants(shipped_page: Path) -> None:
    text = shipped_page.read_text(encoding="utf-8")
    sections = re.findall(r'<section class="task" data-type="([a-z_]+)" id="([^"]+)">(.*?)</section>', text, re.S)
    assert len(sections) == 30
    assert {t: sum(1 for s in sections if s[0] == t) for t in TASK_TYPES} == dict.fromkeys(TASK_TYPES, 5)
    assert "30 of the dataset's 300 tasks: 5 per task type, evenly spaced in task-id order" in text
    shipped = {t.task_id: t for t in load_page_tasks(DATA)}
    for _, task_id, body in sections:
        assert body.count('<div class="utt">') == 15
        assert '<mark class="ins">' in body  # every task has inserted material highlighted
        task = shipped[task_id]
        assert len(task.variants) == 15
        assert f'<dd class="clean">{_escaped(task.clean)}</dd>' in body
        assert f'<dd class="seed">{_escaped(task.seed)}</dd>' in body


def _escaped(text: str) -> str:
    return html.escape(text, quote=True)


def test_the_page_is_self_contained_and_names_no_machine_path(shipped_page: Path) -> None:
    text = shipped_page.read_text(encoding="utf-8")
    for needle in (str(repo_root()), str(shipped_page.parent), "/work/", "/home/", "/tmp/", "file:"):
        assert needle not in text, needle
    assert not re.search(r"<(link|img|iframe)\b|\bsrc=|\bhref=|https?://", text)


def test_every_task_with_all(tiny: Path, tmp_path: Path) -> None:
    out = tmp_path / "all.html"
    assert main(["sample-page", str(tiny), "--out", str(out), "--tasks", "all"]) == 0
    text = out.read_text(encoding="utf-8")
    assert text.count('<section class="task"') == 7 and "All 7 tasks of the dataset." in text


def test_hostile_text_is_escaped(tiny: Path, tmp_path: Path) -> None:
    tasks = [t for t in load_page_tasks(tiny) if t.task_id == "trial_03"]
    text = write_sample_page(tasks, 7, tmp_path / "hostile.html", per_type=1).read_text(encoding="utf-8")
    assert "<script>window.pwned" not in text and "<img" not in text and 'onerror="' not in text
    assert text.count("<script>") == 1  # the page's own
    assert "&lt;script&gt;window.pwned = 1&lt;/script&gt;" in text
    assert "&amp;amp;" in text  # an entity in the data stays text
    assert "kept with failed checks: target_named" in text


def test_bad_input_is_one_line(tiny: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["sample-page", str(tmp_path), "--out", str(tmp_path / "x.html")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "not a dataset folder" in err
    assert main(["sample-page", str(tiny), "--out", str(tmp_path / "missing" / "x.html")]) == 2
    assert "no such folder" in capsys.readouterr().err
    assert main(["sample-page", str(tiny), "--out", str(tmp_path)]) == 2
    assert "is a folder" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main(["sample-page", str(tiny), "--out", str(tmp_path / "x.html"), "--tasks", "0"])
    assert "expected a positive number of tasks per task type or 'all'" in capsys.readouterr().err


def test_the_card_links_the_page_written_beside_it(tiny: Path, tmp_path: Path) -> None:
    folder = tmp_path / "data"
    shutil.copytree(tiny, folder)
    shutil.copy(DATA / "build_stats.json", folder / "build_stats.json")
    from builders.card import write_card

    write_card(folder, json.loads((folder / "build_stats.json").read_text()))
    assert "sample.html" not in (folder / "README.md").read_text()
    assert main(["sample-page", str(folder), "--out", str(folder / "sample.html")]) == 0
    card = (folder / "README.md").read_text()
    assert "[`sample.html`](sample.html)" in card and card.startswith("---\nlicense:")
    from talkdem.instructions import dataset_configs

    dataset_configs.cache_clear()
    assert "memory_bank" in dataset_configs(folder)  # the refreshed card still declares the configs


def test_render_refuses_an_empty_sample() -> None:
    with pytest.raises(ValueError, match="no tasks"):
        render_sample_page([], 0, 5)
