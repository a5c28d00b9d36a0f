"""DementiaBank CHAT transcripts: participant speech, chunked as in the paper (at least 25 words a chunk).

CHAT annotations are removed from the text; retracings with correction (`[//]`, `[///]`) are counted as
repairs before they are removed. DementiaBank is IRB-gated: this reads a folder the user supplies.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

__all__ = ["Chunk", "chunk_transcript", "read_chat_folder"]

_REPAIR = re.compile(r"\[//+\]")
_ANNOTATION = re.compile(
    r"\[[^\]]*\]|<|>|\(\.+\)|&[-=+]?\w+|\+[./!?\"]+|[@%]\w+(?::\w+)*|\x15[^\x15]*\x15|\bxxx\b|\bwww\b"
)
_SPACES = re.compile(r"\s+")


@dataclass(frozen=True)
class Chunk:
    """Consecutive participant utterances of one transcript, at least `min_words` words long."""

    text: str
    repairs: int


def _utterances(path: Path, speaker: str) -> list[str]:
    lines: list[str] = []
    for raw in path.read_text(encoding="utf-8", errors="replace").splitlines():
        if raw.startswith("*"):
            lines.append(raw)
        elif raw.startswith("\t") and lines:  # continuation of the previous tier
            lines[-1] += " " + raw.strip()
        elif raw.startswith(("%", "@")):
            lines.append("")
    return [line.split(":", 1)[1] for line in lines if line.startswith(f"*{speaker}:")]


def _clean(utterance: str) -> str:
    text = _ANNOTATION.sub(" ", utterance)
    text = re.sub(r"\s+([.?!,])", r"\1", _SPACES.sub(" ", text)).strip()
    return text


def chunk_transcript(path: Path, speaker: str = "PAR", min_words: int = 25) -> list[Chunk]:
    chunks: list[Chunk] = []
    texts: list[str] = []
    repairs = 0
    for utterance in _utterances(path, speaker):
        repairs += len(_REPAIR.findall(utterance))
        cleaned = _clean(utterance)
        if cleaned:
            texts.append(cleaned)
        if sum(len(t.split()) for t in texts) >= min_words:
            chunks.append(Chunk(" ".join(texts), repairs))
            texts, repairs = [], 0
    return chunks


def read_chat_folder(folder: Path, min_words: int = 25) -> dict[str, list[Chunk]]:
    """Chunks of `folder/dementia/*.cha` and `folder/control/*.cha`."""
    groups = {}
    for group in ("dementia", "control"):
        files = sorted((folder / group).glob("*.cha"))
        if not files:
            raise FileNotFoundError(f"{folder / group}: no .cha transcripts (expected dementia/ and control/ folders)")
        groups[group] = [c for f in files for c in chunk_transcript(f, min_words=min_words)]
    return groups
