"""What a published file may say about a run: no machine paths, and file names that never collide.

Run headers record what the user typed (`--model ~/models/x.gguf`, a plan file's path, a server
URL). Results, reports and leaderboards are shared, so a model file is named by its file name and its
content hash, configuration paths by their file name, and served endpoints not at all.
"""

from __future__ import annotations

import hashlib
import re
from collections.abc import Mapping, Sequence
from pathlib import PurePosixPath, PureWindowsPath
from typing import Any

from talkdem.paths import file_stem
from talkdem.runs import RunHeader

__all__ = ["is_machine_path", "public_config", "public_header", "public_model", "unique_stems"]

_WEIGHT_SUFFIXES = (".gguf", ".bin", ".safetensors", ".pt", ".pth", ".onnx")
_WINDOWS_DRIVE = re.compile(r"^[A-Za-z]:[\\/]")


def is_machine_path(text: str) -> bool:
    """True for strings naming a place on some machine: absolute, home-relative, `./x`, `C:\\x`, or a
    relative path to a weights file. Hub ids (`org/model`) are not paths."""
    text = text.strip()
    return (
        text.startswith(("/", "~", "./", "../", "\\\\"))
        or bool(_WINDOWS_DRIVE.match(text))
        or (("/" in text or "\\" in text) and text.lower().endswith(_WEIGHT_SUFFIXES))
    )


def _file_name(text: str) -> str:
    name = PureWindowsPath(text).name if "\\" in text else PurePosixPath(text).name
    return name or text.strip("/\\")


def public_model(model: Mapping[str, str]) -> dict[str, str]:
    """`{"backend", "name", "revision"}` with a path reduced to its file name and a URL revision dropped
    (an endpoint address says nothing about the weights and may be private)."""
    name = str(model.get("name", ""))
    revision = str(model.get("revision", ""))
    if is_machine_path(name):
        name = _file_name(name)
    if revision.startswith(("http://", "https://")) or is_machine_path(revision):
        revision = ""
    return {"backend": str(model.get("backend", "")), "name": name, "revision": revision}


def _public_value(value: Any) -> Any:
    if isinstance(value, str):
        if value.startswith(("http://", "https://")):
            return ""
        return _file_name(value) if is_machine_path(value) else value
    if isinstance(value, list | tuple):
        return [_public_value(v) for v in value]
    if isinstance(value, dict):
        return {k: _public_value(v) for k, v in value.items()}
    return value


def public_config(config: Mapping[str, Any]) -> dict[str, Any]:
    """A header's configuration with every path reduced to its file name and every URL dropped."""
    return {key: _public_value(value) for key, value in config.items()}


def public_header(header: RunHeader) -> dict[str, Any]:
    """`RunHeader.to_json()` fit for publishing."""
    record = header.to_json()
    record["model"] = public_model(header.model)
    record["config"] = public_config(header.config)
    return record


def _slug(text: str) -> str:
    # Bounded: a run scored with a long `--model` still gets file names the file system takes.
    return file_stem(text, "run")


def unique_stems(labels: Sequence[str]) -> list[str]:
    """A file-name-safe stem per label, distinct even where labels differ only in spaces, punctuation or
    case (case-insensitive file systems): a clashing stem gets a short hash of its full label."""
    stems = [_slug(label) for label in labels]
    counts: dict[str, int] = {}
    for stem in stems:
        counts[stem.casefold()] = counts.get(stem.casefold(), 0) + 1
    out = []
    for label, stem in zip(labels, stems, strict=True):
        if counts[stem.casefold()] > 1:
            stem = f"{stem}-{hashlib.sha256(label.encode()).hexdigest()[:8]}"
        out.append(stem)
    if len({s.casefold() for s in out}) != len(out):  # identical labels: only their position tells them apart
        out = [f"{stem}-{i + 1}" for i, stem in enumerate(out)]
    return out
