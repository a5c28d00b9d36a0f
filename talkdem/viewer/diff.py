"""A word-level diff of a pattern instruction against its task's clean control: what the pattern inserted
(vague references, the wrong object, filler, a digression, an intrusion) stands out against the words the
two share."""

from __future__ import annotations

import difflib
import re

__all__ = ["word_diff"]

_TOKEN = re.compile(r"\s+|[^\s]+")
_EDGE = re.compile(r"^\W+|\W+$")


def _key(word: str) -> str:
    # Words compare without case and edge punctuation: "lamp," in the pattern still matches "lamp." of the
    # clean text, so only material the pattern really added is marked.
    return _EDGE.sub("", word).casefold() or word


def word_diff(clean: str, text: str) -> list[tuple[str, str]]:
    """`text` as segments `(kind, words)`: `same` (also in `clean`), `ins` (only in `text`) and `del` (clean
    words the pattern dropped or replaced, placed where they were). Joining the `same` and `ins` segments
    gives `text` back exactly."""
    tokens = _TOKEN.findall(text)
    clean_tokens = _TOKEN.findall(clean)
    words = [t for t in tokens if not t.isspace()]
    clean_words = [t for t in clean_tokens if not t.isspace()]
    # Positions of each word in `tokens`, so spacing between words is kept as written.
    where = [i for i, t in enumerate(tokens) if not t.isspace()]
    matcher = difflib.SequenceMatcher(None, [_key(w) for w in clean_words], [_key(w) for w in words], autojunk=False)
    segments: list[tuple[str, str]] = []

    def add(kind: str, piece: str) -> None:
        if not piece:
            return
        if segments and segments[-1][0] == kind:
            segments[-1] = (kind, segments[-1][1] + piece)
        else:
            segments.append((kind, piece))

    def span(start: int, end: int) -> str:
        """Tokens of words start..end-1 of `text`, with the whitespace after each."""
        if start >= end:
            return ""
        last = where[end] if end < len(where) else len(tokens)
        return "".join(tokens[where[start] : last])

    if where:
        add("same", "".join(tokens[: where[0]]))  # leading whitespace
    for op, a0, a1, b0, b1 in matcher.get_opcodes():
        if op in ("delete", "replace"):
            add("del", " ".join(clean_words[a0:a1]))
        if op == "equal":
            add("same", span(b0, b1))
        elif op in ("insert", "replace"):
            add("ins", span(b0, b1))
    if not where:
        add("same", text)
    return segments
