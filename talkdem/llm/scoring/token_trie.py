"""The candidates' token trie: shared beginnings (" find a", " pick up the") become one node.

Both exact scorers walk it: the packed forward pass of `prefix_scorer` runs every node once, and the branch
and bound of `branch_bound` expands nodes best first. Nodes are numbered in creation order; node i stands
for the path from the context to token i, and its row of log-probabilities predicts the token after it.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

__all__ = ["TokenTrie"]


@dataclass
class TokenTrie:
    tokens: list[int] = field(default_factory=list)
    parents: list[int] = field(default_factory=list)
    """-1: the node hangs off the context."""
    depths: list[int] = field(default_factory=list)
    children: list[dict[int, int]] = field(default_factory=list)
    ends: list[int] = field(default_factory=list)
    """The first candidate index ending at each node, or -1."""
    roots: dict[int, int] = field(default_factory=dict)

    @classmethod
    def of(cls, continuations: Sequence[Sequence[int]]) -> TokenTrie:
        """The trie of `continuations`, each ending node marked with its (first) candidate index."""
        trie = cls()
        for index, continuation in enumerate(continuations):
            trie.add_path(continuation, candidate=index)
        return trie

    def new_nodes(self, path: Sequence[int]) -> int:
        """How many nodes inserting `path` would create."""
        level = self.roots
        for depth, token in enumerate(path):
            node = level.get(token)
            if node is None:
                return len(path) - depth
            level = self.children[node]
        return 0

    def add_path(self, path: Sequence[int], candidate: int = -1) -> list[int]:
        """Insert `path`, returning the node of each of its prefixes; `candidate` (>= 0) marks where it ends
        unless an earlier candidate already ends there (duplicates: the earlier one wins, as in full scoring)."""
        nodes = []
        parent, level = -1, self.roots
        for token in path:
            node = level.get(token)
            if node is None:
                node = len(self.tokens)
                self.tokens.append(token)
                self.parents.append(parent)
                self.depths.append(self.depths[parent] + 1 if parent >= 0 else 0)
                self.children.append({})
                self.ends.append(-1)
                level[token] = node
            nodes.append(node)
            parent, level = node, self.children[node]
        if candidate >= 0 and nodes and self.ends[nodes[-1]] == -1:
            self.ends[nodes[-1]] = candidate
        return nodes

    def path(self, node: int) -> list[int]:
        """The tokens from the context to `node`, inclusive."""
        tokens = []
        while node >= 0:
            tokens.append(self.tokens[node])
            node = self.parents[node]
        return tokens[::-1]
