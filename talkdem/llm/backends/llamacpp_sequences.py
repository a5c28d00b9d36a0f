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
4. Memory stays bounded: a sequence holds one context and one search path (after a choice, the context and the
   part of the winner it holds); it is emptied when its episode ends.
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
class _Choice:
    """One open choice: its context is computed (started: the sequence holds a prefix of it), then its search runs."""

    session: int
    context: list[int]
    continuations: Sequence[Sequence[int]]
    started: bool = False
    steps: Generator[Expansion, Sequence[NDArray[np.float64]], BestContinuation] | None = None
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
        f32_kv_cache: float32 keys and values, as the serial scorer (false: llama.cpp's float16).
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
        self.layout = f"sequences-{decode_size}{'' if f32_kv_cache else '-f16'}"
        """What run headers record as `model.scoring`: the decode size and, when float16, the KV cache type."""
        self.held: list[list[int]] = [[] for _ in range(sequences)]
        """The tokens each sequence holds, in position order."""
        self.tokens_evaluated = 0
        self.tokens_copied = 0
        """Context tokens a sequence took from another instead of running them (prefix sharing)."""
        self.decodes = 0
        self._open: dict[int, _Choice] = {}

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
        if session in self._open:
            raise ValueError(f"session {session} still has a choice in flight")
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
        """Run `tokens` (each continuing what its sequence holds; at most `decode_size`) in one decode; return the
        log-probability rows of the tokens marked `read`, in order."""
        lib, batch, rows = self._lib, self._batch, []
        if not 0 < len(tokens) <= self.decode_size:
            raise ValueError(f"a decode holds 1 to {self.decode_size} tokens, got {len(tokens)}")
        for i, item in enumerate(tokens):
            batch.token[i] = item.token
            batch.pos[i] = item.position
            batch.n_seq_id[i] = 1
            batch.seq_id[i][0] = item.sequence
            batch.logits[i] = item.read
        batch.n_tokens = len(tokens)
        status = lib.llama_decode(self._ctx, batch)
        if status == 1:
            raise RuntimeError(
                f"llama.cpp's KV cache ({self.n_ctx} cells for {self.sequences} sequences) is full: "
                "give the model a larger n_ctx (--model-arg n_ctx=...) or fewer episodes in flight"
            )
        if status != 0:
            raise RuntimeError(f"llama_decode failed with status {status}")
        self.decodes += 1
        self.tokens_evaluated += len(tokens)
        for i, item in enumerate(tokens):
            if item.read:
                logits = np.ctypeslib.as_array(lib.llama_get_logits_ith(self._ctx, i), shape=(self.n_vocab,))
                rows.append(log_softmax(logits))
            self.held[item.sequence].append(item.token)
        return rows

    # -- choosing ----------------------------------------------------------------------------------------
    def submit(self, session: int, context: list[int], continuations: Sequence[Sequence[int]]) -> None:
        """Open a choice for `session` (one at a time per session); `step` works on it until it is answered."""
        if not 0 <= session < self.sequences:
            raise ValueError(f"session {session} outside the {self.sequences} sequences of this context")
        if session in self._open:
            raise ValueError(f"session {session} already has a choice in flight")
        if not context:
            raise ValueError("the context must have at least one token")
        if any(len(c) > self.decode_size for c in continuations):
            raise ValueError(f"a continuation longer than {self.decode_size} tokens cannot run in one decode")
        self._open[session] = _Choice(session, list(context), continuations)

    def pending(self) -> bool:
        """Whether a choice is open."""
        return bool(self._open)

    def step(self) -> list[tuple[int, BestContinuation]]:
        """One decode of at most `decode_size` tokens over every open choice's pending work (branch and bound's
        expansions first, then contexts); the (session, answer) of each choice it finished.

        Choices move on independently: while one episode's search still expands, another's next context can fill
        the same decode (continuous batching), so decodes stay full while any work is pending."""
        self._start_contexts()
        tokens: list[_Token] = []
        plan: list[tuple[_Choice, int]] = []  # (choice, rows it reads) in decode order
        for choice in sorted(self._open.values(), key=lambda c: c.session):
            if choice.wanted is None:
                continue
            path, keep = choice.wanted
            base = len(choice.context)
            if len(path) - keep > self.decode_size - len(tokens):
                continue
            self._truncate(choice.session, base + keep)
            tokens += [_Token(choice.session, base + j, path[j], True) for j in range(keep, len(path))]
            plan.append((choice, len(path) - keep))
        for choice in sorted(self._open.values(), key=lambda c: c.session):
            room = self.decode_size - len(tokens)
            if not choice.started or choice.steps is not None or room == 0:
                continue
            held = len(self.held[choice.session])
            end = min(len(choice.context), held + room)
            last = len(choice.context) - 1
            tokens += [_Token(choice.session, p, choice.context[p], p == last) for p in range(held, end)]
            plan.append((choice, 1 if end == len(choice.context) else 0))
        if not tokens:
            if self._open:
                raise AssertionError("open choices but no work: a context waits for itself")
            return []
        rows = self._run(tokens)
        finished: list[tuple[int, BestContinuation]] = []
        offset = 0
        for choice, count in plan:
            mine, offset = rows[offset : offset + count], offset + count
            if choice.steps is None:
                if count:  # the context's last row: the search starts from it
                    choice.steps = search(mine[0], choice.continuations)
                    self._advance(choice, None)
            else:
                self._advance(choice, mine)
            if choice.result is not None:
                self._keep_winner(choice)
                del self._open[choice.session]
                finished.append((choice.session, choice.result))
        return finished

    def _keep_winner(self, choice: _Choice) -> None:
        """Drop the candidates' cells but keep the context and whatever the sequence holds of the winner.

        The next step's context usually continues with the chosen skill, whose tokens branch and bound has
        just run at those very positions: keeping them spares running them again (measured on the 12 episodes
        of issue 47, Vanilla: 434 of 3,979 tokens). Their values come from the search's decode instead of the
        next context's, a difference of batch layout only, which this scorer's numbers already carry."""
        assert choice.result is not None
        base = len(choice.context)
        winner = choice.continuations[choice.result.index]
        self._truncate(choice.session, base + common_prefix_length(self.held[choice.session][base:], winner))

    def _start_contexts(self) -> None:
        """Give each new choice's sequence the longest prefix of its context that any sequence holds (copied, not
        run). A choice whose context shares more with a context being computed now waits until that one holds
        it, then copies it: episodes that retrieved the same CARE demonstrations run them once."""
        computing = [c for c in self._open.values() if c.started and c.steps is None]
        for choice in sorted(self._open.values(), key=lambda c: c.session):
            if choice.started:
                continue
            ids, limit = choice.context, len(choice.context) - 1  # the last token always runs: its row is needed
            own = min(common_prefix_length(self.held[choice.session], ids), limit)
            donor, shared = choice.session, own
            for other in range(self.sequences):
                length = min(common_prefix_length(self.held[other], ids), limit)
                if length > shared:
                    donor, shared = other, length
            ahead = max((min(common_prefix_length(c.context, ids), limit) for c in computing), default=0)
            if ahead >= shared + self.decode_size:
                continue
            if donor != choice.session and shared > own:
                self._adopt(choice.session, donor, shared)
            else:
                self._truncate(choice.session, own)
            choice.started = True
            computing.append(choice)

    def best(
        self, sessions: Sequence[int], contexts: Sequence[list[int]], continuations: Sequence[Sequence[Sequence[int]]]
    ) -> list[BestContinuation]:
        """Each session's best continuation under sum scoring, exactly as branch and bound finds it, all of them
        in shared decodes (`submit` each, then `step` until all are answered)."""
        if len(set(sessions)) != len(sessions):
            raise ValueError("one request per session at a time")
        for session, context, options in zip(sessions, contexts, continuations, strict=True):
            self.submit(session, context, options)
        answers: dict[int, BestContinuation] = {}
        try:
            while len(answers) < len(sessions):
                answers.update(self.step())
        except BaseException:
            self.abandon()
            raise
        return [answers[s] for s in sessions]

    def abandon(self) -> None:
        """Drop every open choice (after an error): their sequences keep only their contexts' computed part."""
        for choice in self._open.values():
            self._truncate(choice.session, min(len(self.held[choice.session]), len(choice.context)))
        self._open.clear()

    @staticmethod
    def _advance(choice: _Choice, rows: Sequence[NDArray[np.float64]] | None) -> None:
        assert choice.steps is not None
        try:
            choice.wanted = next(choice.steps) if rows is None else choice.steps.send(rows)
        except StopIteration as finished:
            choice.result = finished.value
            choice.wanted = None
