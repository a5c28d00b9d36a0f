"""The build: shipped data is up to date, same seed gives the same bytes, a killed build resumes exactly."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from builders.build import BuildResult, CheckpointWarning, build, dataset_files, read_checkpoint
from talkdem.paths import repo_root

DATA = repo_root() / "data"


def test_counts_and_statistics(reference_build: BuildResult) -> None:
    stats = reference_build.stats
    assert stats["counts"] == {"tasks": 300, "instructions": 4800, "memory_tasks": 100, "memory_items": 1600}
    bench = stats["benchmark"]
    assert bench["variants"] == 4500
    assert bench["first_attempt_passed"] + bench["regenerated"] == 4500
    assert bench["verified"] + bench["kept_with_failed_checks"] == 4500


def test_card_copy_matches_the_loader_card() -> None:
    card = (repo_root() / "dataset_card.md").read_text()
    loader_card = (DATA / "README.md").read_text()
    # the markers section may be refreshed by `talkdem markers`; both copies are written together
    assert card == loader_card


def _build_until(out: Path, checkpoint: Path, lines: int, *options: str) -> subprocess.Popen[bytes]:
    """`talkdem build` started in a process, returned once its checkpoint holds `lines` lines (or 180 s passed)."""
    command = [
        sys.executable, "-m", "talkdem", "build", "--out", str(out), "--checkpoint", str(checkpoint),
        "--no-progress", *options,
    ]  # fmt: skip
    process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, cwd=repo_root())
    deadline = time.monotonic() + 180
    while time.monotonic() < deadline:
        if checkpoint.is_file() and checkpoint.read_bytes().count(b"\n") >= lines:
            break
        time.sleep(0.05)
    return process


def test_resume_after_kill_is_byte_identical(reference_build: BuildResult, tmp_path: Path) -> None:
    out, checkpoint = tmp_path / "data", tmp_path / "checkpoint.jsonl"
    process = _build_until(out, checkpoint, 60, "--throttle", "0.02")
    os.kill(process.pid, signal.SIGKILL)
    process.communicate()
    finished = checkpoint.read_bytes().count(b"\n") - 1
    assert 0 < finished < 400, "the build should have been killed mid-way"
    assert not (out / "README.md").exists()

    resumed = build(out, checkpoint=checkpoint, progress=False)
    assert resumed.resumed_units >= finished
    assert dataset_files(out) == dataset_files(reference_build.folder)
    assert not checkpoint.exists()


def test_truncated_checkpoint_line_is_recovered(reference_build: BuildResult, tmp_path: Path) -> None:
    out, checkpoint = tmp_path / "data", tmp_path / "checkpoint.jsonl"
    full = tmp_path / "full.jsonl"
    # a checkpoint with 3 finished units and half of a fourth, as a kill during a write leaves it
    lines = []
    from builders.build import build_unit, checkpoint_header
    from talkdem.speech import get_generator
    from talkdem.tasks import load_tasks

    gen = get_generator("rules")
    lines.append(json.dumps(checkpoint_header(gen, 0, None, load_tasks("benchmark"), load_tasks("memory"))))
    for task in load_tasks("benchmark")[:4]:
        lines.append(
            json.dumps({"unit": f"benchmark:{task.task_id}", "rows": build_unit(gen, task, 0)}, ensure_ascii=False)
        )
    full.write_text("\n".join(lines) + "\n")
    checkpoint.write_text("\n".join(lines[:4]) + "\n" + lines[4][: len(lines[4]) // 2])

    with pytest.warns(CheckpointWarning, match="truncated"):
        result = build(out, checkpoint=checkpoint, progress=False)
    assert result.resumed_units == 3
    assert dataset_files(out) == dataset_files(reference_build.folder)


def test_checkpoint_of_another_build_is_refused_and_kept(tmp_path: Path) -> None:
    from builders.build import read_checkpoint

    checkpoint = tmp_path / "checkpoint.jsonl"
    text = json.dumps({"checkpoint": 1, "generator": "rules", "prompt_version": "x", "seed": 7}) + "\n"
    checkpoint.write_text(text)
    with pytest.raises(ValueError, match="checkpoint of another build"):
        read_checkpoint(checkpoint, {"checkpoint": 1, "generator": "rules", "prompt_version": "x", "seed": 0})
    assert checkpoint.read_text() == text


def test_a_file_that_is_not_a_checkpoint_is_never_overwritten(tmp_path: Path) -> None:
    precious = tmp_path / "notes.txt"
    precious.write_text("three hours of notes\n")
    with pytest.raises(ValueError, match="is not a TALK-Dem build checkpoint"):
        build(tmp_path / "out", checkpoint=precious, progress=False, limit=1)
    assert precious.read_text() == "three hours of notes\n"


def test_a_smoke_build_keeps_the_full_builds_checkpoint() -> None:
    from builders.build import default_checkpoint

    assert default_checkpoint("rules", 0, 3) != default_checkpoint("rules", 0)
    assert default_checkpoint("rules", 0, 3) != default_checkpoint("rules", 0, 4)


def test_the_build_refuses_a_folder_that_is_not_a_dataset(tmp_path: Path) -> None:
    (tmp_path / "README.md").write_text("# my project\n")
    with pytest.raises(ValueError, match="not a TALK-Dem dataset folder"):
        build(tmp_path, checkpoint=tmp_path.parent / "c.jsonl", progress=False, limit=1)
    assert (tmp_path / "README.md").read_text() == "# my project\n"


def test_two_builds_on_one_checkpoint(tmp_path: Path) -> None:
    from builders.checkpoint import CheckpointInUseError, checkpoint_lock

    path = tmp_path / "c.jsonl"
    with checkpoint_lock(path), pytest.raises(CheckpointInUseError, match="another build"):
        build(tmp_path / "out", checkpoint=path, progress=False, limit=1)


def test_another_seed_gives_other_utterances(tmp_path: Path) -> None:
    from builders.build import build_unit
    from talkdem.speech import get_generator
    from talkdem.tasks import load_tasks

    task = load_tasks("benchmark")[0]
    gen = get_generator("rules")
    first, again, other = build_unit(gen, task, 0), build_unit(gen, task, 0), build_unit(gen, task, 1)
    assert first == again
    assert [r["instruction"] for r in first] != [r["instruction"] for r in other]


def test_failing_variants_are_regenerated_then_kept_with_their_checks() -> None:
    from collections.abc import Sequence

    from builders.build import build_unit
    from builders.verification.stats import verification_stats
    from talkdem.speech import GenerationRequest
    from talkdem.speech.rules_v3 import RulesV3Generator
    from talkdem.tasks import load_tasks

    class Flaky:
        """The rules generator's first draw, with the target dropped on a first attempt (topic drift) and
        always (intrusion level 3). One utterance per request: no `generate_candidates` to draw around it."""

        name = "rules"

        def __init__(self) -> None:
            self.rules = RulesV3Generator()
            self.prompt_version = self.rules.prompt_version
            self.seen: set[tuple[str, int]] = set()

        def generate(self, requests: Sequence[GenerationRequest]) -> list[str]:
            out = self.rules.generate(requests)
            for i, r in enumerate(requests):
                first = (r.pattern, r.level) not in self.seen and r.pattern == "topic_drift"
                self.seen.add((r.pattern, r.level))
                if first or (r.pattern == "intrusion" and r.level == 3):
                    out[i] = "Hello! Could you do that thing for me?"
            return out

    rows = build_unit(Flaky(), load_tasks("benchmark")[0], 0)
    by_cell = {(r["pattern"], r["level"]): r["verification"] for r in rows}
    assert by_cell[("topic_drift", 1)] == {"passed": True, "failed_checks": [], "attempts": 2}
    kept = by_cell[("intrusion", 3)]
    assert kept["passed"] is False and kept["attempts"] == 3 and "target_object" in kept["failed_checks"]
    stats = verification_stats(rows)
    assert stats["first_attempt_passed"] == 11 and stats["regenerated"] == 4
    assert stats["second_attempt_passed"] == 3 and stats["third_attempt"] == 1
    assert stats["kept_with_failed_checks"] == 1 and stats["failed_checks"]["target_object"] == 1


class _Stop(Exception):
    """Stands in for a kill after a number of finished units."""


def _interrupted_full_build(monkeypatch: pytest.MonkeyPatch, checkpoint: Path, out: Path, units: int) -> bytes:
    import builders.build as build_module

    real = build_module.build_unit
    calls = {"n": 0}

    def stopping(*args: object, **kwargs: object) -> object:
        if calls["n"] == units:
            raise _Stop
        calls["n"] += 1
        return real(*args, **kwargs)  # type: ignore[arg-type]

    monkeypatch.setattr(build_module, "build_unit", stopping)
    with pytest.raises(_Stop):
        build(out, checkpoint=checkpoint, progress=False)
    monkeypatch.setattr(build_module, "build_unit", real)
    saved = checkpoint.read_bytes()
    assert saved.count(b"\n") == units + 1  # the settings line and the finished units
    return saved


def test_a_different_build_never_deletes_or_reuses_a_checkpoint(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    checkpoint = tmp_path / "checkpoint.jsonl"
    saved = _interrupted_full_build(monkeypatch, checkpoint, tmp_path / "full", units=3)
    settings = json.loads(saved.splitlines()[0])
    assert settings["limit"] is None and settings["smoke"] is False and settings["seed"] == 0
    assert settings["generator"] == "rules" and len(settings["tasks_sha256"]) == 64
    # A smoke build given the same --checkpoint: refused with one line, the full build's units untouched.
    command = [sys.executable, "-m", "talkdem", "build", "--out", str(tmp_path / "smoke"), "--limit", "1"]
    result = subprocess.run(
        [*command, "--checkpoint", str(checkpoint), "--no-progress"], capture_output=True, text=True, timeout=300
    )
    assert result.returncode == 2 and "Traceback" not in result.stderr
    assert len(result.stderr.strip().splitlines()) == 1
    assert "checkpoint of another build" in result.stderr and "limit" in result.stderr
    assert checkpoint.read_bytes() == saved
    assert not (tmp_path / "smoke").exists() or not any((tmp_path / "smoke").iterdir())
    # Another seed, or other task files, are other builds too; a torn last line of another build's
    # checkpoint is not cut either.
    with pytest.raises(ValueError, match="checkpoint of another build"):
        build(tmp_path / "other", checkpoint=checkpoint, progress=False, seed=1)
    torn = saved + b'{"unit": "benchmark:half'
    checkpoint.write_bytes(torn)
    with pytest.raises(ValueError, match="checkpoint of another build"):
        build(tmp_path / "other", checkpoint=checkpoint, progress=False, limit=2)
    assert checkpoint.read_bytes() == torn
    # The same build's settings still find its 3 finished units (resuming it in full takes a minute).
    from builders.build import checkpoint_header
    from talkdem.speech import get_generator
    from talkdem.tasks import load_tasks

    checkpoint.write_bytes(saved)
    same = checkpoint_header(get_generator("rules"), 0, None, load_tasks("benchmark"), load_tasks("memory"))
    assert len(read_checkpoint(checkpoint, same)) == 3 and checkpoint.read_bytes() == saved


def test_workers_write_the_same_bytes_as_one_process(tmp_path: Path) -> None:
    from builders.build import build_unit, checkpoint_header
    from talkdem.speech import get_generator
    from talkdem.tasks import load_tasks

    one = build(tmp_path / "one", checkpoint=tmp_path / "one.jsonl", progress=False, limit=6)
    # a checkpoint holding the first task already: the workers build only the other eleven units
    gen = get_generator("rules")
    bench, memory = load_tasks("benchmark")[:6], load_tasks("memory")[:6]
    first = {"unit": f"benchmark:{bench[0].task_id}", "rows": build_unit(gen, bench[0], 0)}
    checkpoint = tmp_path / "two.jsonl"
    checkpoint.write_text(
        json.dumps(checkpoint_header(gen, 0, 6, bench, memory)) + "\n" + json.dumps(first, ensure_ascii=False) + "\n"
    )
    two = build(tmp_path / "two", checkpoint=checkpoint, progress=False, limit=6, workers=2)
    assert two.resumed_units == 1
    assert dataset_files(two.folder) == dataset_files(one.folder)
    assert not checkpoint.exists()


def test_workers_need_the_generator_by_name(tmp_path: Path) -> None:
    from talkdem.speech import get_generator

    with pytest.raises(ValueError, match="needs the generator by name"):
        build(tmp_path / "out", generator=get_generator("rules"), progress=False, limit=1, workers=2)
    with pytest.raises(ValueError, match="workers must be a positive number"):
        build(tmp_path / "out", progress=False, limit=1, workers=0)


def test_a_build_with_workers_stops_on_sigterm_and_resumes(reference_build: BuildResult, tmp_path: Path) -> None:
    out, checkpoint = tmp_path / "data", tmp_path / "checkpoint.jsonl"
    process = _build_until(out, checkpoint, 40, "--workers", "2", "--throttle", "0.05")
    process.send_signal(signal.SIGTERM)
    _, stderr = process.communicate(timeout=120)  # the workers are terminated, not waited for
    assert process.returncode != 0 and b"Traceback" not in stderr, stderr.decode()
    assert stderr.decode().strip().splitlines()[-1] == (
        "talkdem build: terminated (finished tasks are saved in the checkpoint; run again to resume)"
    )
    finished = checkpoint.read_bytes().count(b"\n") - 1
    assert 0 < finished < 400
    assert not (out / "README.md").exists()

    resumed = build(out, checkpoint=checkpoint, progress=False, workers=2)
    assert resumed.resumed_units >= finished
    assert dataset_files(out) == dataset_files(reference_build.folder)
