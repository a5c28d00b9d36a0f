"""The exact SayCan choice under sum scoring, scoring only a fraction of the candidates' tokens.

A candidate's summed log-probability is at most the partial sum over any of its prefixes, because every
log-probability is <= 0. So a best-first walk over the candidates' token trie, ordered by partial sums, can
stop as soon as the best item in its queue is a complete candidate: no prefix left in the queue, and so no
candidate below one, can score higher. The answer is exactly the argmax of full scoring (ties: the earlier
candidate, as full scoring breaks them), found after expanding only the prefixes that score above it.

Expanding a trie node means running its path's tokens after the context to read the distribution of the next
token. The backend holds one path at a time (llama.cpp's sequence, a transformers cache), so `evaluate` is
told how many leading tokens of the new path it still holds and runs only the rest. A node with a single
child is expanded together with that child in the same call: on a CPU a few tokens in one batch cost about
what one does, since reading the weights dominates.
"""

from __future__ import annotations

import heapq
from collections.abc import Callable, Generator, Sequence

import numpy as np
from numpy.typing import NDArray

from talkdem.llm.interface.base import BestContinuation
from talkdem.llm.scoring.token_trie import TokenTrie

__all__ = ["BestContinuation", "Evaluate", "Expansion", "best_continuation", "common_prefix_length", "search"]

Evaluate = Callable[[Sequence[int], int], Sequence[NDArray[np.float64]]]
"""`evaluate(path, keep)`: hold context + `path`, running only `path[keep:]` (the first `keep` tokens are still
held from the previous call); return the log-probability rows after `path[: j + 1]` for j = keep .. len - 1."""


def common_prefix_length(a: Sequence[int], b: Sequence[int]) -> int:
    """Leading tokens `a` and `b` share (how much of a held sequence a backend can keep)."""
    count = 0
    for x, y in zip(a, b, strict=False):
        if x != y:
            break
        count += 1
    return count


_COMPLETE, _EXPAND = 0, 1  # at equal bounds a finished candidate pops first


Expansion = tuple[list[int], int]
"""What `search` asks for: (path, keep), the arguments of one `Evaluate` call."""


def best_continuation(
    first: NDArray[np.float64], continuations: Sequence[Sequence[int]], evaluate: Evaluate
) -> BestContinuation:
    """The continuation with the highest summed log-probability.

    Args:
        first: log-probabilities of the first token after the context.
        continuations: token ids, each non-empty.
        evaluate: runs trie paths after the context (see `Evaluate`).
    """
    steps = search(first, continuations)
    try:
        wanted = next(steps)
        while True:
            wanted = steps.send(evaluate(*wanted))
    except StopIteration as finished:
        result: BestContinuation = finished.value
        return result


def search(
    first: NDArray[np.float64], continuations: Sequence[Sequence[int]]
) -> Generator[Expansion, Sequence[NDArray[np.float64]], BestContinuation]:
    """`best_continuation` as a step machine: it yields each expansion (path, keep) it needs and takes the
    rows `Evaluate` would return, so that a backend can run the expansions of many searches in one batch
    (the multi-sequence llama.cpp scorer). The search is the same, expansion for expansion."""
    if not continuations:
        raise ValueError("no continuations to choose from")
    if any(len(c) == 0 for c in continuations):
        raise ValueError("every continuation must have at least one token")
    trie = TokenTrie.of(continuations)
    scores = [0.0] * len(trie.tokens)
    queue: list[tuple[float, int, int]] = []

    def reached(node: int, score: float, expanded_next: bool) -> None:
        scores[node] = score
        if trie.ends[node] >= 0:
            heapq.heappush(queue, (-score, _COMPLETE, trie.ends[node]))
        if trie.children[node] and not expanded_next:
            heapq.heappush(queue, (-score, _EXPAND, node))

    for token, node in trie.roots.items():
        reached(node, float(first[token]), expanded_next=False)
    held: list[int] = []
    tokens_evaluated = expansions = 0
    while queue:
        negative, kind, item = heapq.heappop(queue)
        if kind == _COMPLETE:
            return BestContinuation(item, -negative, tokens_evaluated, expansions)
        chain = [item]  # follow single-child links: their rows come in the same call
        while len(trie.children[chain[-1]]) == 1:
            (only,) = trie.children[chain[-1]].values()
            if not trie.children[only]:
                break
            chain.append(only)
        path = trie.path(chain[-1])
        start = trie.depths[item]
        keep = min(common_prefix_length(held, path), start)
        rows = yield path, keep
        held = path
        tokens_evaluated += len(path) - keep
        expansions += len(chain)
        for offset, node in enumerate(chain):
            row = rows[start - keep + offset]
            following = chain[offset + 1] if offset + 1 < len(chain) else -1
            for token, child in trie.children[node].items():
                reached(child, scores[node] + float(row[token]), expanded_next=child == following)
    raise AssertionError("unreachable: every trie path ends in a candidate")
