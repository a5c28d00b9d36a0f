"""The project's import graph has no cycles, between files or between packages.

Imports are read from the source (``ast``), at every depth: an import inside a function counts as much as one at the
top, because a lazy import still ties the two modules together. A package here is a top-level package (``builders``,
``care``, ``evaluate_talkdem``, ``perf``) or a subpackage of ``talkdem`` (``talkdem.runs``, ``talkdem.cli``...); a cycle
between packages means neither can be read, tested or moved without the other, even when no two files import each
other.
"""

from __future__ import annotations

import ast
from collections.abc import Iterable, Mapping
from pathlib import Path

import pytest

from talkdem.paths import repo_root

PACKAGES = ("talkdem", "care", "builders", "evaluate_talkdem", "perf")
MODULES_AT_TOP = ("talk_dem.py",)


def _module_files() -> dict[str, Path]:
    root = repo_root()
    files: dict[str, Path] = {}
    for package in PACKAGES:
        for path in sorted((root / package).rglob("*.py")):
            parts = path.relative_to(root).with_suffix("").parts
            files[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    for name in MODULES_AT_TOP:
        files[Path(name).stem] = root / name
    return files


def _imported(module: str, path: Path, known: Mapping[str, Path]) -> set[str]:
    """The project modules ``module`` imports: ``from a import b`` names ``a.b`` where that is a module, else ``a``."""
    here = module.split(".") if path.name == "__init__.py" else module.split(".")[:-1]
    found: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            found |= {alias.name for alias in node.names if alias.name in known}
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parent = here[: len(here) - (node.level - 1)]
                base = ".".join([*parent, base] if base else parent)
            for alias in node.names:
                if f"{base}.{alias.name}" in known:
                    found.add(f"{base}.{alias.name}")
                elif base in known:
                    found.add(base)
    found.discard(module)
    return found


def _cycles(graph: Mapping[str, Iterable[str]]) -> list[list[str]]:
    """Strongly connected components of more than one node (Tarjan's algorithm, iterative)."""
    index: dict[str, int] = {}
    lowest: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    components: list[list[str]] = []
    for start in graph:
        if start in index:
            continue
        work: list[tuple[str, list[str]]] = [(start, sorted(graph[start]))]
        index[start] = lowest[start] = len(index)
        stack.append(start)
        on_stack.add(start)
        while work:
            node, pending = work[-1]
            if pending:
                child = pending.pop()
                if child not in index:
                    index[child] = lowest[child] = len(index)
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, sorted(graph[child])))
                elif child in on_stack:
                    lowest[node] = min(lowest[node], index[child])
                continue
            work.pop()
            if work:
                lowest[work[-1][0]] = min(lowest[work[-1][0]], lowest[node])
            if lowest[node] == index[node]:
                component = []
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    component.append(member)
                    if member == node:
                        break
                if len(component) > 1:
                    components.append(sorted(component))
    return components


def _package(module: str) -> str:
    parts = module.split(".")
    return ".".join(parts[:2]) if parts[0] == "talkdem" and len(parts) > 1 else parts[0]


@pytest.fixture(scope="module")
def file_graph() -> dict[str, set[str]]:
    files = _module_files()
    return {module: _imported(module, path, files) for module, path in files.items()}


def test_the_graph_is_read(file_graph: dict[str, set[str]]) -> None:
    # The check below is only as good as the reading: a few imports it must see, at the top and inside a function.
    assert "talkdem.runs.episode_files" in file_graph["talkdem.runs.store"] | file_graph["talkdem.runs.runner"]
    assert "talkdem.cli" in file_graph["talkdem.__main__"]
    assert any(edge.startswith("builders.") for edge in file_graph["talkdem.cli.build"])  # imported inside run()


def test_no_two_files_import_each_other_at_any_depth(file_graph: dict[str, set[str]]) -> None:
    assert _cycles(file_graph) == []


def test_no_two_packages_import_each_other_at_any_depth(file_graph: dict[str, set[str]]) -> None:
    packages: dict[str, set[str]] = {}
    for module, imported in file_graph.items():
        packages.setdefault(_package(module), set()).update(_package(name) for name in imported)
    for package, imported in list(packages.items()):
        imported.discard(package)
        for name in imported:
            packages.setdefault(name, set())
    assert _cycles(packages) == []


def test_a_cycle_is_found() -> None:
    assert _cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
    assert _cycles({"a": {"b"}, "b": set()}) == []
