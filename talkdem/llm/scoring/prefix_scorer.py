"""Scoring many continuations of one context fast: SayCan's inner loop.

SayCan scores every vocabulary skill (214) given the same prompt at every step. Done naively that is one
full forward pass of prompt + skill per candidate. Here:

1. The context runs once and its key/value cache is kept. The next call reuses the longest common token
   prefix with the previous context (the next SayCan step appends a few tokens; the next episode shares
   the few-shot examples), so only new tokens are run.
2. All candidates run in ONE forward pass over the cached prefix: their tokens are merged into a trie
   (shared beginnings such as " find a" or " pick up the" run once) and packed into a single sequence with
   a block attention mask (each trie node sees the prefix and its own ancestors) and position ids that
   continue from the prefix length along each branch. The cache is then cut back to the prefix.

3. When only the best candidate under sum scoring is wanted, `best` finds it exactly by branch and bound over
   the same trie (`talkdem.llm.scoring.branch_bound`), running one path at a time over the cached prefix.

`naive_scores` is the reference implementation the tests compare against.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
import torch
from numpy.typing import NDArray

from talkdem.llm.scoring.branch_bound import BestContinuation, best_continuation
from talkdem.llm.scoring.token_trie import TokenTrie

__all__ = ["PrefixCachedScorer", "naive_scores"]


def _crop(cache: Any, length: int) -> None:
    """Cut a transformers DynamicCache back to `length` tokens (the API changed sign across versions)."""
    excess = cache.get_seq_length() - length
    if excess > 0:
        cache.crop(-excess)


class PrefixCachedScorer:
    """Continuation log-likelihoods over a reused prefix cache, all candidates in one packed pass."""

    def __init__(self, model: Any, max_packed_tokens: int = 2048) -> None:
        self.model = model
        self.max_packed_tokens = max_packed_tokens
        self._cache: Any = None
        self._cached_ids: list[int] = []
        self._next_logprobs: torch.Tensor | None = None

    def reset(self) -> None:
        self._cache, self._cached_ids, self._next_logprobs = None, [], None

    @torch.no_grad()
    def _advance_to(self, context_ids: Sequence[int]) -> torch.Tensor:
        """Bring the cache to exactly `context_ids`; return log p(next token | context)."""
        from transformers import DynamicCache

        if not context_ids:
            raise ValueError("the context must have at least one token")
        common = 0
        for cached, new in zip(self._cached_ids, context_ids, strict=False):
            if cached != new:
                break
            common += 1
        if common == len(context_ids) == len(self._cached_ids) and self._next_logprobs is not None:
            return self._next_logprobs
        if self._cache is None:
            self._cache = DynamicCache(config=self.model.config)
        # Keep at least one token to run, so that the last position's logits exist.
        keep = min(common, len(context_ids) - 1)
        _crop(self._cache, keep)
        feed = torch.tensor([list(context_ids[keep:])])
        positions = torch.arange(keep, len(context_ids))[None]
        # Only the last position's logits are needed: skipping the vocabulary projection of the others saves
        # a large share of a long prefix pass.
        out = self.model(
            input_ids=feed, past_key_values=self._cache, position_ids=positions, use_cache=True, logits_to_keep=1
        )
        self._cached_ids = list(context_ids)
        self._next_logprobs = torch.log_softmax(out.logits[0, -1].float(), dim=-1)
        return self._next_logprobs

    @torch.no_grad()
    def _packed_pass(self, trie: TokenTrie, prefix_length: int) -> torch.Tensor:
        """Log-probabilities after every trie node, from one forward pass over the cached prefix."""
        count = len(trie.tokens)
        visible = torch.zeros(count, prefix_length + count, dtype=torch.bool)
        visible[:, :prefix_length] = True
        for node in range(count):
            ancestor = node
            while ancestor >= 0:
                visible[node, prefix_length + ancestor] = True
                ancestor = trie.parents[ancestor]
        mask = torch.zeros(visible.shape, dtype=torch.float32)
        mask.masked_fill_(~visible, torch.finfo(torch.float32).min)
        positions = torch.tensor([[prefix_length + d for d in trie.depths]])
        out = self.model(
            input_ids=torch.tensor([trie.tokens]),
            attention_mask=mask[None, None],
            position_ids=positions,
            past_key_values=self._cache,
            use_cache=True,
        )
        _crop(self._cache, prefix_length)
        return torch.log_softmax(out.logits[0].float(), dim=-1)

    @torch.no_grad()
    def best(self, context_ids: Sequence[int], continuations: Sequence[Sequence[int]]) -> BestContinuation:
        """The continuation with the highest summed log-probability, by branch and bound (exact)."""
        first = self._advance_to(context_ids).double().numpy()
        prefix_length = len(context_ids)

        def evaluate(path: Sequence[int], keep: int) -> list[NDArray[np.float64]]:
            _crop(self._cache, prefix_length + keep)
            out = self.model(
                input_ids=torch.tensor([list(path[keep:])]),
                position_ids=torch.arange(prefix_length + keep, prefix_length + len(path))[None],
                past_key_values=self._cache,
                use_cache=True,
            )
            rows = torch.log_softmax(out.logits[0].double(), dim=-1).numpy()
            return list(rows)

        try:
            return best_continuation(first, continuations, evaluate)
        finally:
            _crop(self._cache, prefix_length)

    def score(self, context_ids: Sequence[int], continuations: Sequence[Sequence[int]]) -> list[float]:
        """Summed log p(continuation | context) for each continuation (token ids, each non-empty)."""
        if any(len(c) == 0 for c in continuations):
            raise ValueError("every continuation must have at least one token")
        first = self._advance_to(context_ids)
        prefix_length = len(context_ids)
        scores = [float(first[c[0]]) for c in continuations]
        # Only tokens that are followed by another token of the same continuation need a forward pass.
        pending = [i for i, c in enumerate(continuations) if len(c) > 1]
        start = 0
        while start < len(pending):
            trie = TokenTrie()
            paths: dict[int, list[int]] = {}
            end = start
            while end < len(pending):
                index = pending[end]
                path = continuations[index][:-1]
                if end > start and len(trie.tokens) + trie.new_nodes(path) > self.max_packed_tokens:
                    break  # over budget: run this chunk, start a new trie with the rest
                paths[index] = trie.add_path(path)
                end += 1
            logprobs = self._packed_pass(trie, prefix_length)
            for index, nodes in paths.items():
                continuation = continuations[index]
                scores[index] += float(sum(logprobs[node, continuation[j + 1]] for j, node in enumerate(nodes)))
            start = end
        return scores


@torch.no_grad()
def naive_scores(model: Any, context_ids: Sequence[int], continuations: Sequence[Sequence[int]]) -> list[float]:
    """One full forward pass of context + continuation per candidate (the slow, obvious reference)."""
    scores = []
    n = len(context_ids)
    for continuation in continuations:
        ids = torch.tensor([list(context_ids) + list(continuation)])
        logprobs = torch.log_softmax(model(input_ids=ids).logits[0].float(), dim=-1)
        scores.append(float(sum(logprobs[n - 1 + j, token] for j, token in enumerate(continuation))))
    return scores
