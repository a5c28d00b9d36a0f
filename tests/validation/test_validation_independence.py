"""The validation never loads the generator's or the verifier's vocabulary, and the generator never loads it."""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

from talkdem.paths import repo_root

ROOT = repo_root()
FORBIDDEN = ("talkdem.speech", "builders.generation", "builders.verification", "builders.markers")
# talkdem.speech holds the generator, its lexicon and the verifier's cue lists. builders.markers as a whole:
# importing any of its modules runs its __init__, which imports the measures and, through them, those cue lists.


def _imports(path: Path) -> set[str]:
    """Every module a file imports, at any depth (function-level imports included)."""
    names: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(), filename=str(path))):
        if isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module:
            names.add(node.module)
            names.update(f"{node.module}.{alias.name}" for alias in node.names)
    return names


def _hits(names: set[str], prefixes: tuple[str, ...]) -> set[str]:
    return {n for n in names if any(n == p or n.startswith(p + ".") for p in prefixes)}


def test_validation_source_imports_nothing_of_the_generator_side() -> None:
    files = sorted((ROOT / "builders" / "validation").glob("*.py"))
    assert len(files) >= 8  # the package is there to be checked
    found = {str(f.relative_to(ROOT)): _hits(_imports(f), FORBIDDEN) for f in files}
    assert {f: h for f, h in found.items() if h} == {}


def test_generator_never_imports_the_validation() -> None:
    files = [*(ROOT / "builders" / "generation").rglob("*.py"), *(ROOT / "talkdem" / "speech").rglob("*.py")]
    assert files
    found = {str(f.relative_to(ROOT)): _hits(_imports(f), ("builders.validation",)) for f in files}
    assert {f: h for f, h in found.items() if h} == {}


def test_importing_the_validation_loads_no_generator_module() -> None:
    # the source check misses what an imported module imports in turn; a fresh interpreter shows it
    code = (
        "import sys\n"
        "import builders.validation, builders.validation.markers, builders.validation.report\n"
        "import builders.validation.fluency, builders.validation.variety, builders.validation.pipeline\n"
        f"print(sorted(m for m in sys.modules if m.startswith({FORBIDDEN!r})))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=ROOT)
    assert out.stdout.strip() == "[]"


def test_the_paper_table_copy_matches_the_markers_package() -> None:
    from builders.markers.paper import FLOORS as MARKER_FLOORS
    from builders.markers.paper import PAPER as MARKER_PAPER
    from builders.markers.report import DIRECTIONS as MARKER_DIRECTIONS
    from builders.validation.paper import DIRECTIONS, FLOORS, PAPER

    assert PAPER == MARKER_PAPER
    assert FLOORS == MARKER_FLOORS
    assert {(m, p): s for m, p, s in MARKER_DIRECTIONS} == DIRECTIONS
