"""Many episodes' SayCan steps in shared llama.cpp decodes: one context, one sequence per episode in flight.

The serial scorer (`LlamaCppLM.best_token_continuation`) sends branch and bound's expansions to llama.cpp a few
tokens at a time, and a CPU spends about 16 ms per token at that size where a 32-token batch costs about 10.6
(`../shared/design/batching.md`, measured on the project's 2-core machine). With several episodes in flight, the
scheduler (`talkdem.runs.scheduler`) hands over every episode's pending choice at once, and this scorer runs all
their work together, as llama.cpp's own multiple-choice scorer (`tools/perplexity`, `hellaswag_score`) does:

1. Each episode in flight (`session`) owns a sequence of one context with a unified KV cache. Its context is
   extended from what the sequence already holds; a prefix that another sequence holds (the few-shot examples,
   CARE demonstrations that several episodes retrieved) is not run again but copied (`llama_memory_seq_cp`,
   which in a unified cache only tags the cells with one more sequence id). Episodes whose contexts share more
   than any sequence holds run in waves: the first computes the shared part, the others copy it.
2. Branch and bound runs as a step machine per episode (`branch_bound.search`): each round, every unfinished
   search's next expansion goes into the same decodes, logits only at the positions read.
3. Decodes hold at most `decode_size` (32) tokens from any sequences, in a fixed order (session, then
   position). On the measured CPU a token's logits depended on the batch's length, not on its place in it nor on
   the other sequences' tokens, up to 32 tokens per decode; batches are not padded to a fixed length (branch and
   bound's last rounds hold a few tokens, and padding them to 32 cost more than batching saved), so a step's
   values depend on what ran beside it, to within llama.cpp's batch-layout noise. The same command gives the
   same rounds and the same records; a resumed or sharded run agrees with an uninterrupted one to that noise
   (docs/performance.md gives the measured agreement). Branch and bound stays exact with respect to the scores
   it computes.
4. Memory stays bounded: a sequence holds one context and one search path; it is emptied when its episode ends.
"""

from __future__ import annotations

from collections.abc import Generator, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from talkdem.llm.interface.base import BestContinuation
from talkdem.llm.scoring.branch_bound import Expansion, common_prefix_length, search

__all__ = ["SequenceScorer", "log_softmax"]

_FLASH_ATTENTION_DISABLED = 0  # llama_flash_attn_type: the serial contexts run without it too
_GGML_TYPE_F32 = 0


def log_softmax(logits: NDArray[np.float32]) -> NDArray[np.float64]:
    values = logits.astype(np.float64)
    shifted = values - values.max()
    result: NDArray[np.float64] = shifted - np.log(np.exp(shifted).sum())
    return result


@dataclass
class _Token:
    sequence: int
    position: int
    token: int
    read: bool
    """Whether this position's logits are read (the last context token, every token of an expansion)."""


@dataclass
class _Search:
    session: int
    context: list[int]
    steps: Generator[Expansion, Sequence[NDArray[np.float64]], BestContinuation]
    wanted: Expansion | None = None
    result: BestContinuation | None = None


class SequenceScorer:
    """A multi-sequence llama.cpp context on an already loaded model's weights.

    Args:
        model: the `llama_model` pointer (the weights are shared with the serial contexts, mapped once).
        n_vocab: the vocabulary size.
        sequences: episodes in flight at most (one sequence each).
        n_ctx: KV cells of the whole context, shared by all sequences (prefixes held by several count once).
        threads: CPU threads (llama.cpp's default when None).
        f32_kv_cache: float32 keys and values, as the serial scorer.
        decode_size: most tokens in one `llama_decode`.
    """

    def __init__(
        self,
        model: Any,
        n_vocab: int,
        sequences: int,
        n_ctx: int,
        threads: int | None,
        f32_kv_cache: bool,
        decode_size: int = 32,
    ) -> None:
        import llama_cpp

        self._lib = llama_cpp
        params = llama_cpp.llama_context_default_params()
        params.n_ctx = n_ctx
        params.n_batch = decode_size
        params.n_ubatch = decode_size
        params.n_seq_max = sequences
        params.kv_unified = True
        params.flash_attn_type = _FLASH_ATTENTION_DISABLED
        if threads is not None:
            params.n_threads = params.n_threads_batch = threads
        if f32_kv_cache:
            params.type_k = params.type_v = _GGML_TYPE_F32
        self._ctx = llama_cpp.llama_init_from_model(model, params)
        if not self._ctx:
            raise RuntimeError(f"llama.cpp could not create a context of {n_ctx} cells for {sequences} sequences")
        self._memory = llama_cpp.llama_get_memory(self._ctx)
        self._batch = llama_cpp.llama_batch_init(decode_size, 0, 1)
        self.n_vocab = n_vocab
        self.sequences = sequences
        self.n_ctx = n_ctx
        self.decode_size = decode_size
        self.held: list[list[int]] = [[] for _ in range(sequences)]
        """The tokens each sequence holds, in position order."""
        self.tokens_evaluated = 0
        self.tokens_copied = 0
        """Context tokens a sequence took from another instead of running them (prefix sharing)."""
        self.decodes = 0

    def close(self) -> None:
        if self._ctx:
            self._lib.llama_batch_free(self._batch)
            self._lib.llama_free(self._ctx)
            self._ctx = None

    def __del__(self) -> None:
        self.close()

    # -- sequences ---------------------------------------------------------------------------------------
    def free(self, session: int) -> None:
        """Empty the sequence of an episode that ended."""
        self._lib.llama_memory_seq_rm(self._memory, session, -1, -1)
        self.held[session] = []

    def _truncate(self, session: int, length: int) -> None:
        if length < len(self.held[session]):
            self._lib.llama_memory_seq_rm(self._memory, session, length, -1)
            del self.held[session][length:]

    def _adopt(self, session: int, donor: int, length: int) -> None:
        """Make `session` hold the first `length` tokens of `donor` (no computation: the cells are shared)."""
        self._lib.llama_memory_seq_rm(self._memory, session, -1, -1)
        self._lib.llama_memory_seq_cp(self._memory, donor, session, 0, length)
        self.tokens_copied += length
        self.held[session] = self.held[donor][:length]

    # -- decoding ----------------------------------------------------------------------------------------
    def _run(self, tokens: Sequence[_Token]) -> list[NDArray[np.float64]]:
        """Run `tokens` (each continuing what its sequence holds) in decodes of at most `decode_size`; return the
        log-probability rows of the tokens marked `read`, in order."""
        lib, batch, rows = self._lib, self._batch, []
        for start in range(0, len(tokens), self.decode_size):
            part = tokens[start : start + self.decode_size]
            for i, item in enumerate(part):
                batch.token[i] = item.token
                batch.pos[i] = item.position
                batch.n_seq_id[i] = 1
                batch.seq_id[i][0] = item.sequence
                batch.logits[i] = item.read
            batch.n_tokens = len(part)
            status = lib.llama_decode(self._ctx, batch)
            if status == 1:
                raise RuntimeError(
                    f"llama.cpp's KV cache ({self.n_ctx} cells for {self.sequences} sequences) is full: "
                    "give the model a larger n_ctx (--model-arg n_ctx=...) or fewer episodes in flight"
                )
            if status != 0:
                raise RuntimeError(f"llama_decode failed with status {status}")
            self.decodes += 1
            self.tokens_evaluated += len(part)
            for i, item in enumerate(part):
                if item.read:
                    logits = np.ctypeslib.as_array(lib.llama_get_logits_ith(self._ctx, i), shape=(self.n_vocab,))
                    rows.append(log_softmax(logits))
                self.held[item.sequence].append(item.token)
        return rows

    def _extend(self, sessions: Sequence[int], contexts: Sequence[list[int]]) -> list[NDArray[np.float64]]:
        """Make each session's sequence hold its context; return log p(next token | context) per session.

        A context's last token is always run (its row is what the search starts from). A session takes the
        longest prefix any sequence holds; when an earlier session of this call will hold a longer one, it
        waits for the next wave and copies it from there."""
        first: dict[int, NDArray[np.float64]] = {}
        waiting = list(range(len(sessions)))
        while waiting:
            wave, later = [], []
            for order, index in enumerate(waiting):
                session, ids = sessions[index], contexts[index]
                limit = len(ids) - 1
                own = min(common_prefix_length(self.held[session], ids), limit)
                donor, shared = session, own
                for other in range(self.sequences):
                    length = min(common_prefix_length(self.held[other], ids), limit)
                    if length > shared:
                        donor, shared = other, length
                ahead = max((min(common_prefix_length(contexts[j], ids), limit) for j in waiting[:order]), default=0)
                if ahead >= shared + self.decode_size:  # an earlier context in this wave computes more of it
                    later.append(index)
                    continue
                if donor != session and shared > own:
                    self._adopt(session, donor, shared)
                else:
                    self._truncate(session, own)
                wave.append(index)
            tokens = [
                _Token(sessions[i], p, contexts[i][p], p == len(contexts[i]) - 1)
                for i in wave
                for p in range(len(self.held[sessions[i]]), len(contexts[i]))
            ]
            for i, row in zip(wave, self._run(tokens), strict=True):
                first[i] = row
            waiting = later
        return [first[i] for i in range(len(sessions))]

    # -- choosing ----------------------------------------------------------------------------------------
    def best(
        self, sessions: Sequence[int], contexts: Sequence[list[int]], continuations: Sequence[Sequence[Sequence[int]]]
    ) -> list[BestContinuation]:
        """Each session's best continuation under sum scoring, exactly as branch and bound finds it, every
        session's expansions of one round in shared decodes."""
        if len(set(sessions)) != len(sessions):
            raise ValueError("one request per session at a time")
        for session in sessions:
            if not 0 <= session < self.sequences:
                raise ValueError(f"session {session} outside the {self.sequences} sequences of this context")
        rows = self._extend(sessions, contexts)
        searches = [
            _Search(s, list(c), search(row, options))
            for s, c, row, options in zip(sessions, contexts, rows, continuations, strict=True)
        ]
        for item in searches:
            self._advance(item, None)
        try:
            while active := [s for s in searches if s.result is None]:
                tokens: list[_Token] = []
                counts = []
                for item in active:
                    assert item.wanted is not None
                    path, keep = item.wanted
                    base = len(item.context)
                    self._truncate(item.session, base + keep)
                    tokens += [_Token(item.session, base + j, path[j], True) for j in range(keep, len(path))]
                    counts.append(len(path) - keep)
                results = self._run(tokens)
                offset = 0
                for item, count in zip(active, counts, strict=True):
                    self._advance(item, results[offset : offset + count])
                    offset += count
        finally:
            for item in searches:  # the candidates are gone; each context stays for its next step
                self._truncate(item.session, len(item.context))
        return [item.result for item in searches if item.result is not None]

    @staticmethod
    def _advance(item: _Search, rows: Sequence[NDArray[np.float64]] | None) -> None:
        try:
            item.wanted = next(item.steps) if rows is None else item.steps.send(rows)
        except StopIteration as finished:
            item.result = finished.value
            item.wanted = None
