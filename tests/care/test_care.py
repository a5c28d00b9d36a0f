"""CARE: top-k retrieval over the real memory bank with the real encoder, and the care package's boundaries."""

from __future__ import annotations

import ast
from pathlib import Path

import numpy as np
import pytest
from scripted_lm import ScriptedLM

from care.retrieval import top_k
from talkdem.instructions import load_memory_bank
from talkdem.paths import repo_root
from talkdem.planner.strategies import load_strategy


def test_top_k_is_ordered_and_stable() -> None:
    memory = np.eye(4)
    query = np.array([[0.9, 0.1, 0.1, 0.0]])
    assert top_k(query / np.linalg.norm(query), memory, 3) == [[0, 1, 2]]
    with pytest.raises(ValueError):
        top_k(query, memory, 5)


@pytest.mark.slow
def test_care_retrieves_from_the_same_task_for_a_memory_instruction(tmp_path, monkeypatch) -> None:  # type: ignore[no-untyped-def]
    monkeypatch.setenv("TALKDEM_CACHE_DIR", str(tmp_path))
    care = load_strategy("care")
    memory = load_memory_bank()
    probe = next(m for m in memory if m.condition.pattern == "intrusion" and m.condition.level == 3)
    retrieved = care.retrieve([probe.instruction])[0]  # type: ignore[attr-defined]
    assert retrieved[0].id == probe.id  # an instruction is most similar to itself
    assert len(retrieved) == 3 and len({m.id for m in retrieved}) == 3
    assert list(tmp_path.glob("care/memory-*.npy")), "memory embeddings are cached on disk"
    prepared = care.prepare([probe.instruction], ScriptedLM(["done"]))[0]
    assert len(prepared.demonstrations) == 3 and prepared.notes["retrieved"].startswith(probe.id)


def test_ties_keep_the_lower_index() -> None:
    memory = np.array([[1.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    assert top_k(np.array([[1.0, 0.0]]), memory, 2) == [[0, 1]]


def _imported_modules(path: Path) -> set[str]:
    names: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            names |= {alias.name for alias in node.names}
        elif isinstance(node, ast.ImportFrom) and node.module:
            names.add(node.module)
    return names


# The commands that build the dataset are the only runtime code allowed to reach the build pipeline.
BUILD_COMMANDS = {
    "build.py", "replay.py", "select.py", "markers.py", "push.py", "verify.py", "retrieval.py", "sample_page.py",
    "validate.py",
}  # fmt: skip
# The clarification track's simulated person speaks its answers with the dataset's own generator (issue 23: the
# answer under the instruction's pattern and level), and the run spec records that generator's version.
GENERATOR_USERS = {"talkdem/clarify/person.py", "talkdem/runs/spec.py"}


@pytest.mark.parametrize("package", ["talkdem", "care"])
def test_nothing_at_run_time_imports_the_builders(package: str) -> None:
    offenders = [
        str(path.relative_to(repo_root()))
        for path in sorted((repo_root() / package).rglob("*.py"))
        if not (path.parent.name == "cli" and path.name in BUILD_COMMANDS)
        and str(path.relative_to(repo_root())) not in GENERATOR_USERS
        and any(name == "builders" or name.startswith("builders.") for name in _imported_modules(path))
    ]
    assert offenders == []


def test_order_and_dedupe_options() -> None:
    from golden_support import bag_of_words

    from care.strategy import ContextAwareRetrieval

    memory = load_memory_bank()
    probe = next(m for m in memory if m.condition.pattern == "intrusion" and m.condition.level == 3)
    plain = ContextAwareRetrieval(memory=memory, encode=bag_of_words)
    retrieved = plain.retrieve([probe.instruction])[0]
    assert retrieved[0].id == probe.id  # an instruction is most similar to itself
    shown = plain.prepare([probe.instruction], ScriptedLM(["done"]))[0]
    assert [d.instruction for d in shown.demonstrations] == [m.instruction for m in reversed(retrieved)]  # best last
    first = ContextAwareRetrieval(memory=memory, encode=bag_of_words, order="best_first")
    shown_first = first.prepare([probe.instruction], ScriptedLM(["done"]))[0]
    assert [d.instruction for d in shown_first.demonstrations] == [m.instruction for m in retrieved]
    deduped = ContextAwareRetrieval(memory=memory, encode=bag_of_words, dedupe=True)
    items = deduped.retrieve([probe.instruction])[0]
    assert len(items) == 3 and len({m.task_id for m in items}) == 3 and items[0].id == probe.id
    assert deduped.options() == {"k": 3, "order": "best_last", "dedupe": True}
    with pytest.raises(ValueError, match="CARE order must be one of"):
        ContextAwareRetrieval(memory=memory, encode=bag_of_words, order="middle")  # type: ignore[arg-type]


def test_an_encoder_passed_in_never_writes_the_shared_cache(tmp_path, monkeypatch) -> None:  # type: ignore[no-untyped-def]
    # Keyed by MiniLM's name, another encoder's memory embeddings would be read back by every later CARE run.
    from golden_support import bag_of_words

    from care.strategy import ContextAwareRetrieval

    monkeypatch.setenv("TALKDEM_CACHE_DIR", str(tmp_path))
    care = ContextAwareRetrieval(memory=load_memory_bank(), encode=bag_of_words)
    assert care.embeddings.shape == (len(care.memory), 512)
    assert not list(tmp_path.rglob("*.np*"))
