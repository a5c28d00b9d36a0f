"""TALK-Dem: the one-call loader, with the dataset's vocabulary re-exported from `talkdem.schema`.

The dataset folder (`data/` here, or the Hub repository) loads with `datasets` alone, through the YAML
`configs` of its README.md; this module is a convenience. The patterns, levels, conditions, layout and
features are declared in `talkdem.schema` (the light module everything else imports).
It deliberately lives outside the dataset folder: `datasets` refuses a folder `foo/` holding `foo.py`.

    >>> import talk_dem
    >>> talk_dem.load("topic_drift", 3)          # doctest: +SKIP
    Dataset({features: [...], num_rows: 300})
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import datasets

from talkdem.schema import (
    ALL,
    CLEAN,
    CONDITIONS,
    CONFIGS,
    LEVELS,
    PATTERNS,
    TASK_TYPES,
    Condition,
    Pattern,
    default_split,
    features,
    split_name,
)

__all__ = [
    "ALL",
    "CLEAN",
    "CONDITIONS",
    "CONFIGS",
    "INSTRUCTION_FEATURES",
    "LEVELS",
    "MEMORY_BANK_FEATURES",
    "PATTERNS",
    "TASK_FEATURES",
    "TASK_TYPES",
    "Condition",
    "Pattern",
    "data_dir",
    "load",
    "split_name",
]

INSTRUCTION_FEATURES = features("instruction")
"""One instruction (clean control or pattern variant) of the 300 benchmark tasks."""

MEMORY_BANK_FEATURES = features("memory_bank")
"""One CARE memory item: an instruction of a held-out task, its gold interpretation and reference plan."""

TASK_FEATURES = features("task")
"""Task metadata: the seed, its parameters, the scene's object types and the reference plan."""


def data_dir() -> str:
    """The dataset folder this package reads, for `datasets.load_dataset(talk_dem.data_dir(), CONFIG, ...)`:
    `$TALKDEM_DATA_DIR`, the checkout's `data/`, else the copy bundled in the installed wheel (a bare
    `load_dataset("data", ...)` only works in a checkout's root, and would look for `data` on the Hub)."""
    from talkdem.paths import data_dir as folder

    return str(folder())


def _default_folder() -> str:
    return data_dir()


def load(
    pattern: str, level: int | None = None, *, split: str | None = None, path: str | None = None, **kwargs: Any
) -> datasets.Dataset:
    """One split: `load("intrusion", 2)`, `load("clean")`, `load("memory_bank")`, `load("tasks")`,
    `load("tasks", split="memory")`.

    `path` is a dataset folder or a Hub repository id (`ORG/talk-dem`; read from the Hugging Face cache
    when offline). The default is the dataset this package carries: `data/` of a checkout, the copy in
    the installed wheel, or `$TALKDEM_DATA_DIR`. A local folder is cached by its files' content (under
    `cache_dir`, default the Hugging Face datasets cache, in `talkdem-local/<content hash>/`), so an edited
    or another folder is never answered with stale rows. Other keyword arguments go to `datasets.load_dataset`.
    The clean control is level 0 in episode ids (`<task>:clean:0`), so `load("clean", 0)` is accepted.
    """
    if pattern in PATTERNS:
        if level not in LEVELS:
            raise ValueError(f"pattern '{pattern}' needs a level in {LEVELS}, got {level}")
        chosen = split_name(level)
    elif pattern in CONFIGS:
        if level not in (None, 0) or (level == 0 and pattern != CLEAN):
            raise ValueError(f"config '{pattern}' has no levels")
        chosen = default_split(pattern)
    else:
        raise ValueError(f"unknown config '{pattern}': expected one of {', '.join(CONFIGS)}")
    if split is not None and pattern in PATTERNS and split != chosen:
        raise ValueError(f"give either a level or a split for '{pattern}', not both ({level} vs '{split}')")
    source = path or _default_folder()
    if path and not Path(path).exists() and path.count("/") != 1:
        raise ValueError(f"'{path}' is neither a dataset folder nor a Hub repository id (ORG/NAME)")
    if Path(source).is_dir():
        # `datasets` keys a local folder's cache by its name and the declared patterns, not by the files'
        # bytes: every folder called `data`, and every edit of one, would be answered with the rows cached
        # first. A cache folder per content makes what is loaded what is on disk.
        base = kwargs.pop("cache_dir", None) or datasets.config.HF_DATASETS_CACHE
        kwargs["cache_dir"] = str(Path(base) / "talkdem-local" / _content_key(Path(source)))
    result = datasets.load_dataset(source, pattern, split=split or chosen, **kwargs)
    assert isinstance(result, datasets.Dataset)
    return result


def _content_key(folder: Path) -> str:
    """sha256 (first 24 digits) over the folder's dataset card and Parquet files, names and bytes."""
    import hashlib

    digest = hashlib.sha256()
    files = [folder / "README.md", *sorted(folder.rglob("*.parquet"))]
    for path in files:
        if path.is_file():
            digest.update(path.relative_to(folder).as_posix().encode() + b"\0" + path.read_bytes() + b"\0")
    return digest.hexdigest()[:24]
