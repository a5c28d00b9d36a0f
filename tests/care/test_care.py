"""CARE: top-k retrieval over the real memory bank with the real encoder, and the care package's boundaries."""

from __future__ import annotations

import ast
import re
import subprocess
import sys
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
    assert list(tmp_path.glob("embeddings/*/*.npz")), "memory embeddings are cached on disk"
    prepared = care.prepare([probe.instruction], ScriptedLM(["done"]))[0]
    assert len(prepared.demonstrations) == 3 and prepared.notes["retrieved"].startswith(probe.id)


def test_ties_keep_the_lower_index() -> None:
    memory = np.array([[1.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    assert top_k(np.array([[1.0, 0.0]]), memory, 2) == [[0, 1]]


def _imported_modules(path: Path) -> set[str]:
    """Every module `path` imports, at any depth (imports inside functions count), and every `module:attribute`
    string it holds (a registry entry imports its module when it is looked up)."""
    names: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            names |= {alias.name for alias in node.names}
        elif isinstance(node, ast.ImportFrom) and node.module:
            names.add(node.module)
        elif isinstance(node, ast.Constant) and isinstance(node.value, str):
            target = re.fullmatch(r"([A-Za-z_][\w.]*):[A-Za-z_]\w*", node.value)
            if target:
                names.add(target.group(1))
    return names


# The commands that build the dataset are the only runtime code allowed to reach the build pipeline.
BUILD_COMMANDS = {
    "build.py", "replay.py", "select.py", "markers.py", "push.py", "verify.py", "retrieval.py", "sample_page.py",
    "validate.py",
}  # fmt: skip
RUNTIME = ["talkdem", "care", "perf", "evaluate_talkdem", "talk_dem.py"]
"""The library, the CARE strategy, the performance checks, the `evaluate` entry point and the top-level
`talk_dem` module: everything a user of the benchmark runs (the builders are for rebuilding the dataset)."""


@pytest.mark.parametrize("part", RUNTIME)
def test_nothing_at_run_time_imports_the_builders(part: str) -> None:
    root = repo_root() / part
    files = sorted(root.rglob("*.py")) if root.is_dir() else [root]
    assert files and all(path.is_file() for path in files)
    offenders = [
        str(path.relative_to(repo_root()))
        for path in files
        if not (path.parent == repo_root() / "talkdem" / "cli" and path.name in BUILD_COMMANDS)
        and any(name == "builders" or name.startswith("builders.") for name in _imported_modules(path))
    ]
    assert offenders == []


def test_speaking_in_pattern_loads_no_builders_module() -> None:
    # the source check sees what each file names; a fresh interpreter shows what speaking loads in turn
    code = (
        "import sys\n"
        "from talkdem.speech import GenerationRequest, get_generator\n"
        "from talkdem.tasks import load_tasks\n"
        "task = load_tasks('benchmark')[0]\n"
        "clean = get_generator('rules').generate([GenerationRequest(task, 'clean', 0, '', 1)])[0]\n"
        "assert get_generator('rules').generate([GenerationRequest(task, 'topic_drift', 3, clean, 2)])[0]\n"
        "print(sorted(m for m in sys.modules if m == 'builders' or m.startswith('builders.')))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=repo_root())
    assert out.stdout.strip() == "[]"


def test_the_import_check_sees_imports_inside_functions_and_registry_targets(tmp_path: Path) -> None:
    module = tmp_path / "m.py"
    module.write_text(
        'def f():\n    from builders.build import build\n\nTARGET = "builders.generation.llm:LLMGenerator"\n'
    )
    assert _imported_modules(module) == {"builders.build", "builders.generation.llm"}


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
