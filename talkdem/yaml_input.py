"""The one YAML reader for what the package takes from a user (sweep specs, the dataset card's front matter).

`yaml.safe_load` builds only plain values, but it still takes three kinds of input that no caller can handle
after the fact, so they are refused here, while composing, before anything is built or expanded:

- an alias bomb ("billion laughs"): a few lines whose aliases expand into billions of nodes. Aliases are
  allowed (a spec may share a mapping), but the document's size counted with every alias expanded is bounded,
  and so is its nesting (PyYAML composes recursively);
- a duplicate key at any depth, which YAML would resolve silently by keeping the last;
- values Python refuses to build (an integer of thousands of digits, a date such as 2024-02-30), which
  would otherwise surface as a `ValueError` naming neither the file nor the line.

Every refusal is a `YamlInputError` (a `ValueError`) with the 1-based line in the text and the problem, for
the caller to prefix with its file. PyYAML is imported only when something is read.
"""

from __future__ import annotations

import functools
from typing import Any

__all__ = ["MAX_CHARS", "MAX_DEPTH", "MAX_NODES", "YamlInputError", "load_yaml"]

MAX_CHARS = 1_000_000
"""Characters of YAML text read at most (a spec or a card's front matter is a few kilobytes)."""
MAX_NODES = 100_000
"""Nodes of a document with every alias expanded (a sweep spec has tens, the dataset card a few hundred)."""
MAX_DEPTH = 64
"""Nesting of collections (a sweep spec nests four deep)."""


class YamlInputError(ValueError):
    """YAML text that is refused; `line` is 1-based in the text given (None when no line is known); `syntax`:
    the text is not YAML at all (rather than YAML refused by the bounds, a duplicate key or a value)."""

    def __init__(self, line: int | None, problem: str, *, syntax: bool = False) -> None:
        super().__init__(f"line {line}: {problem}" if line is not None else problem)
        self.line = line
        self.problem = problem
        self.syntax = syntax


def load_yaml(text: str) -> Any:
    """The value of the YAML document `text` (safe tags only), or `YamlInputError` naming the line."""
    import yaml

    if len(text) > MAX_CHARS:
        raise YamlInputError(None, f"{len(text):,} characters of YAML; at most {MAX_CHARS:,} are read")
    loader_class, refused = _classes()
    loader = loader_class(text)
    try:
        return loader.get_single_data()
    except yaml.YAMLError as error:
        mark = getattr(error, "problem_mark", None) or getattr(error, "context_mark", None)
        problem = getattr(error, "problem", None) or str(error).splitlines()[0]
        context = getattr(error, "context", None)
        if context:  # "while scanning a quoted scalar", "expected a single document in the stream"
            problem = f"{context}, {problem}"
        syntax = not isinstance(error, refused)
        raise YamlInputError(mark.line + 1 if mark is not None else None, problem, syntax=syntax) from None
    finally:
        loader.dispose()


def _brief(value: object) -> str:
    """A scalar's text as a message quotes it: one line, at most 40 characters."""
    text = " ".join(str(value).split())
    return text if len(text) <= 40 else f"{text[:40]}..."


@functools.cache
def _classes() -> tuple[type, type]:
    """(the loader, the error of its refusals), made once on first use: PyYAML is imported only then."""
    import yaml
    from yaml.nodes import MappingNode, Node, SequenceNode

    class Refused(yaml.MarkedYAMLError):  # type: ignore[misc]  # PyYAML has no type stubs here
        """Valid YAML that this reader refuses (a bound, a duplicate key, a value Python cannot build)."""

    merge_tag = "tag:yaml.org,2002:merge"

    class BoundedLoader(yaml.SafeLoader):  # type: ignore[misc]
        def __init__(self, stream: str) -> None:
            super().__init__(stream)
            # id(node) -> its size with aliases expanded (the tree keeps every node alive, so ids are unique)
            self._sizes: dict[int, int] = {}
            self._depth = 0

        def compose_node(self, parent: Node | None, index: Any) -> Node:
            if self.check_event(yaml.AliasEvent):
                # The anchored node itself, already sized: the parent counts its size once more.
                return super().compose_node(parent, index)
            start = self.peek_event().start_mark
            self._depth += 1
            try:
                if self._depth > MAX_DEPTH:
                    raise Refused(None, None, f"nested deeper than {MAX_DEPTH} levels", start)
                node = super().compose_node(parent, index)
            finally:
                self._depth -= 1
            self._sizes[id(node)] = size = 1 + sum(self._size(child, start) for child in _children(node))
            if size > MAX_NODES:
                raise Refused(
                    None,
                    None,
                    f"expands into more than {MAX_NODES:,} values (aliases counted as what they repeat)",
                    start,
                )
            return node

        def _size(self, node: Node, mark: Any) -> int:
            size = self._sizes.get(id(node))
            if size is None:  # an alias of a collection still being composed: it would contain itself
                raise Refused(None, None, "an alias refers to a collection that contains it", mark)
            return size

        def construct_mapping(self, node: MappingNode, deep: bool = False) -> dict[Any, Any]:
            seen: dict[Any, int] = {}
            for key_node, _ in node.value:
                if key_node.tag == merge_tag or not isinstance(key_node, yaml.ScalarNode):
                    continue  # merged keys may be overridden by design; a collection key is refused below
                key = self.construct_object(key_node)
                line = key_node.start_mark.line + 1
                try:
                    first = seen.get(key)
                except TypeError:  # unhashable: the constructor's own error says so
                    continue
                if first is not None:
                    raise Refused(
                        None,
                        None,
                        f"duplicate key '{_brief(key_node.value)}' (first on line {first}); "
                        "YAML would keep only the last",
                        key_node.start_mark,
                    )
                seen[key] = line
            mapping: dict[Any, Any] = super().construct_mapping(node, deep=deep)
            return mapping

        def construct_object(self, node: Node, deep: bool = False) -> Any:
            try:
                return super().construct_object(node, deep=deep)
            except (ValueError, OverflowError) as error:
                # Python's own refusal of a value YAML resolved (a huge integer, a 30th of February).
                message = str(error).splitlines()[0] if str(error) else type(error).__name__
                raise Refused(None, None, f"cannot read '{_brief(node.value)}': {message}", node.start_mark) from None

    def _children(node: Node) -> list[Node]:
        if isinstance(node, SequenceNode):
            return list(node.value)
        if isinstance(node, MappingNode):
            return [part for pair in node.value for part in pair]
        return []

    return BoundedLoader, Refused
