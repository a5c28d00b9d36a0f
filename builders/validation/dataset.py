"""A dataset folder as the validation reads it: the clean controls and every pattern x level cell."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

__all__ = ["CLEAN", "COLUMNS", "Cell", "cell_key", "ranking_models", "read_cells"]

CLEAN = "clean"
COLUMNS = ("task_id", "instruction", "clean_instruction", "seed_instruction", "scene_objects", "pddl_params")


@dataclass(frozen=True)
class Cell:
    """One split of the benchmark: the clean controls (pattern `clean`, level 0) or one pattern at one level."""

    pattern: str
    level: int
    abbreviation: str
    rows: tuple[dict[str, Any], ...]

    @property
    def key(self) -> str:
        return cell_key(self.pattern, self.level)


def cell_key(pattern: str, level: int) -> str:
    return CLEAN if pattern == CLEAN else f"{pattern}:{level}"


def _read(path: Path) -> list[dict[str, Any]]:
    import pyarrow.parquet as pq  # heavy: only here

    if not path.is_file():
        raise FileNotFoundError(f"{path}: not a TALK-Dem dataset folder (this split is missing)")
    names = set(pq.read_schema(path).names)
    missing = [c for c in (*COLUMNS, "prompt_version") if c not in names]
    if missing:
        raise ValueError(f"{path}: missing column(s) {', '.join(missing)}")
    rows: list[dict[str, Any]] = pq.read_table(path, columns=[*COLUMNS, "prompt_version"]).to_pylist()
    return rows


def read_cells(folder: Path) -> list[Cell]:
    """The clean cell first, then the patterns in the benchmark's order, levels 1-3."""
    from talkdem.schema import LEVELS, PATTERNS, split_name

    if not folder.is_dir():
        raise FileNotFoundError(f"{folder}: no such dataset folder")
    cells = [Cell(CLEAN, 0, "clean", tuple(_read(folder / "clean" / "test.parquet")))]
    for pattern, info in PATTERNS.items():
        for level in LEVELS:
            rows = _read(folder / pattern / f"{split_name(level)}.parquet")
            cells.append(Cell(pattern, level, info.abbreviation, tuple(rows)))
    return cells


def ranking_models(folder: Path) -> list[str]:
    """The models that ranked the rows of a dataset folder (none for an unranked build, or for one written
    before rows had a `ranking` field)."""
    import pyarrow.parquet as pq

    models: set[str] = set()
    for path in sorted(folder.glob("*/*.parquet")):
        if "ranking" not in pq.read_schema(path).names:
            continue
        for ranking in pq.read_table(path, columns=["ranking"]).column("ranking").to_pylist():
            if ranking and ranking.get("model"):
                models.add(ranking["model"])
    return sorted(models)
