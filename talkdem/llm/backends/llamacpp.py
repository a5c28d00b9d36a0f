"""llama.cpp in process (llama-cpp-python, the optional extra `llamacpp`): GGUF files on CPU.

Prompt log-likelihoods are read from the logits of every evaluated position (`logits_all=True`), never
from `create_completion(echo=True, logprobs=...)`, which is off by one position for models without a BOS
token such as SmolLM2. Scoring many continuations of one context (SayCan's inner loop):

1. The context is evaluated once. The next call keeps the longest common token prefix with what the
   context already holds (the next SayCan step appends a few tokens; the next episode shares the few-shot
   examples) and evaluates only the rest.
2. Candidates are visited in token order, so consecutive candidates share their beginnings (" find a",
   " pick up the"): for each one the context is cut back (`n_tokens`) to the prompt plus the part shared
   with the previous candidate, and only the candidate's remaining tokens are evaluated. Its last token
   never needs a pass (its probability comes from the position before it).
3. When only the best candidate under sum scoring is wanted (SayCan's default), `best_continuation` finds it
   exactly by branch and bound over the candidates' token trie (`talkdem.llm.scoring.branch_bound`), running only
   the prefixes that score above the winner.

The context is evaluated in chunks at fixed positions (`context_chunk`, 16 tokens: [0, 16), [16, 32), ...,
then the rest), whatever the cache held before. llama.cpp's quantized kernels give a position other values
depending on the batch it runs in (its length and its place in it): on the default model (Q4_K_M) the same
step scored 0.12-0.46 nats apart when the cache had held the previous steps (each adding a few tokens) and
when it started empty. With the batch layout a function of the context alone, a step's scores do not depend
on which episode or step ran before it, so a run split into shards or resumed scores every step as one
uninterrupted run does. The cost is the last partial chunk, run again at each step (8 tokens on average).
Generation (CoT's hint, TOCC's rewrite, the generative and ReAct planners' steps) runs in a second context on
the same weights (memory-mapped once), made on first use: from an empty cache for the same reason, and with only
the last position's logits computed, which is all sampling needs. The scoring context keeps what it held, so the
next episode's scoring still reuses the few-shot prefix (measured on CoT: the scoring context had been re-run from
the start after every hint, about a third of an episode's time).
"""

from __future__ import annotations

import itertools
import os
from collections.abc import Sequence
from pathlib import Path
from typing import Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from talkdem.llm.backends.llamacpp_sequences import SequenceScorer, log_softmax
from talkdem.llm.backends.tokenizing import GGUFTokenSplit
from talkdem.llm.interface.base import LanguageModel, ModelIdentity, cut_at_stop, file_sha256, loglikelihood_by_context
from talkdem.llm.interface.models import get_model, model_path
from talkdem.llm.interface.options import BackendOption
from talkdem.llm.interface.requests import ChoiceRequest, GenerateRequest, LoglikelihoodRequest
from talkdem.llm.scoring.branch_bound import BestContinuation, best_continuation, common_prefix_length

__all__ = ["LlamaCppLM"]

# TALK-Dem is not on PyPI, so `pip install 'talkdem[llamacpp]'` finds nothing: name what works (the extra's
# one requirement, from pyproject.toml; or the extra of a checkout or of the wheel file).
_MISSING = (
    "llama-cpp-python is not installed (the `llamacpp` extra): `pip install 'llama-cpp-python[server]==0.3.36'`, "
    "or from a checkout `pip install -e '.[llamacpp]'`, or with the wheel `pip install 'PATH/TO/talkdem-VERSION-"
    "py3-none-any.whl[llamacpp]'`; it compiles llama.cpp, about 5-6 minutes on 2 cores (on a virtual machine "
    "whose CPU reports Intel AMX, with CMAKE_ARGS leaving AMX out, as the Makefile's setup-test target does)"
)

_GGML_TYPE_F32 = 0  # ggml_type enum value of float32


def _resolve(model: str) -> tuple[Path, str, str]:
    """(file, name, SHA-256): a catalog model by short name (verified when joined), or any GGUF file."""
    spec = get_model(model)
    if spec is not None:
        return model_path(spec.name), spec.name, spec.sha256
    path = Path(model).expanduser()
    if not path.is_file():
        raise FileNotFoundError(
            f"{model}: the llamacpp backend needs a GGUF file or a model name (`talkdem models` lists them)"
        )
    return path, str(path), file_sha256(path)


def _log_sum_exp(logits: NDArray[np.float32]) -> float:
    values = logits.astype(np.float64)
    peak = float(values.max())
    return peak + float(np.log(np.exp(values - peak).sum()))


def _grammar(json_schema: str) -> Any:
    """The GBNF grammar of a JSON schema, for plain completions (chat completions build it themselves)."""
    from llama_cpp.llama_grammar import LlamaGrammar

    return LlamaGrammar.from_json_schema(json_schema, verbose=False)


class LlamaCppLM(LanguageModel):
    """A GGUF model run by llama.cpp in this process.

    Generation applies the GGUF's chat template (system and user messages) and constrains decoding to a
    request's JSON schema with a grammar (`supports_json_schema`).

    Args:
        model: a GGUF file, or a model's short name (`talkdem models`; `default`: Qwen2.5-Coder-0.5B-Instruct).
        n_ctx: context length in tokens; the logits of every position are kept (n_ctx x vocabulary floats).
        threads: CPU threads (llama.cpp's default when None).
        chat_template: wrap generation prompts in the GGUF's chat template when it has one.
        f32_kv_cache: keep keys and values in float32, or in llama.cpp's default float16. Unset: float32 for
            the serial scorer, float16 for the multi-sequence one. A float16 cache makes serial scores depend on
            how tokens were split into batches (measured: 0.07 nats between the prefix-reusing and the
            from-scratch scorer on a SayCan prompt; float32: equal to 1e-12), which would undo the fixed chunk
            layout. The multi-sequence scorer's values carry batch-layout noise either way (up to 0.5 nats),
            and there float16 halves the cache that every token's attention reads (measured on the 12 episodes
            of issue 47, speed-up over serial: Vanilla x1.71 against x1.59, CARE x1.70 against x1.32;
            docs/performance.md).
        context_chunk: the context's batch layout (see the module docstring); the run header records it
            (`model.scoring`), since scores differ between layouts.
        sequences: episodes in flight (`talkdem run --concurrency N` sets it): above 1, the choices of all of
            them run in shared decodes of one multi-sequence context (`llamacpp_sequences`), with its own layout
            (`model.scoring` `sequences-32-f16`, or `sequences-32` with a float32 cache); the KV cache then
            holds n_ctx x ceil(sequences / 2) cells.
    """

    supports_json_schema = True
    options: ClassVar[tuple[BackendOption, ...]] = (
        BackendOption("n_ctx", "int", "context length in tokens", minimum=1),
        BackendOption("threads", "int", "CPU threads (llama.cpp's default when unset)", minimum=1),
        BackendOption("n_batch", "int", "tokens evaluated per batch", minimum=1),
        BackendOption("chat_template", "bool", "wrap generation prompts in the GGUF's chat template"),
        BackendOption("seed", "int", "the sampler's seed", minimum=0),
        BackendOption(
            "f32_kv_cache", "bool", "float32 keys and values (default: serially yes, with several sequences no)"
        ),
        BackendOption("context_chunk", "int", "the context runs in chunks at fixed positions of this size", minimum=2),
        BackendOption("sequences", "int", "episodes scored together in one multi-sequence context", minimum=1),
    )

    def __init__(
        self,
        model: str,
        n_ctx: int = 4096,
        threads: int | None = None,
        n_batch: int = 512,
        chat_template: bool = True,
        seed: int = 0,
        f32_kv_cache: bool | None = None,
        context_chunk: int = 16,
        sequences: int = 1,
    ) -> None:
        if context_chunk < 2 or context_chunk >= n_batch:
            # A last chunk of one token joins the one before, so a chunk can be context_chunk + 1 tokens long.
            raise ValueError(f"context_chunk must be between 2 and n_batch - 1 ({n_batch - 1}), got {context_chunk}")
        # OpenMP worker threads spin while waiting by default, which collapses throughput on a shared,
        # busy CPU (measured: 2.3x slower); it reads this once, when llama.cpp's library is loaded.
        os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")
        try:
            from llama_cpp import Llama
        except ImportError as error:
            raise ImportError(_MISSING) from error
        path, name, sha256 = _resolve(model)
        self.path = path
        serial_f32 = f32_kv_cache is not False  # unset: float32 serially, float16 with several sequences
        self._context_options: dict[str, Any] = {
            "model_path": str(path),
            "n_ctx": n_ctx,
            "n_batch": n_batch,
            "n_threads": threads,
            "n_threads_batch": threads,
            "seed": seed,
            "flash_attn": False,
            "type_k": _GGML_TYPE_F32 if serial_f32 else None,  # None: llama.cpp's default (float16)
            "type_v": _GGML_TYPE_F32 if serial_f32 else None,
            "verbose": False,
        }
        self._llm: Any = Llama(logits_all=True, **self._context_options)
        self._generator: Any = None
        """The generation context (`_generation_context`), made on first use."""
        self.context_chunk = context_chunk
        self._canonical = 0
        """Leading cached positions computed in full chunks at their fixed places (reusable as they are)."""
        self._sequences: SequenceScorer | None = None
        if sequences > 1:
            self._sequences = SequenceScorer(
                self._llm._model.model,
                self._llm.n_vocab(),
                sequences,
                n_ctx=n_ctx * -(-sequences // 2),
                threads=threads,
                f32_kv_cache=bool(f32_kv_cache),
            )
        self.streams_choices = self._sequences is not None
        layout = self._sequences.layout if self._sequences else f"chunk-{context_chunk}"
        self.identity = ModelIdentity(backend="llamacpp", name=name, revision=sha256, scoring=layout)
        self.use_chat_template = chat_template and bool(self._llm.metadata.get("tokenizer.chat_template"))
        self.split = GGUFTokenSplit(self._llm)
        self._next_logprobs: NDArray[np.float64] | None = None
        self.tokens_evaluated = 0
        """Tokens run through the model so far (context and candidates): what `make bench` compares."""

    def forget_context(self) -> None:
        """Drop the held context: the next call runs its prompt from scratch (as a new process would)."""
        self._llm.reset()
        self._next_logprobs = None
        self._canonical = 0

    def _eval_tail(self, context: Sequence[int], path: Sequence[int], common: int) -> None:
        """Hold context + path, running `path[common:]` (the context and `path[:common]` are still held).

        llama.cpp computes a one-token batch with other kernels than a longer one: measured on SmolLM2 Q4_1,
        a SayCan candidate scored 0.16 nats apart, while batches of two or more tokens agree with one
        from-scratch pass to 1e-14 however they are split. So a single new token runs together with the one
        before it (about the same cost on a CPU), and every score is the from-scratch score.
        """
        start = len(context) + common
        if len(path) - common == 1:
            start -= 1
            # The context's last position is run again here, outside its chunk: not reusable as it was.
            self._canonical = min(self._canonical, start // self.context_chunk * self.context_chunk)
        self._llm.n_tokens = start
        self._eval([*context, *path][start:])

    def _eval(self, tokens: Sequence[int]) -> None:
        self.tokens_evaluated += len(tokens)
        self._llm.eval(list(tokens))

    def runtime(self) -> dict[str, str]:
        """llama-cpp-python's version and the CPU features its llama.cpp was compiled with: the package is
        built from source on each machine (`make setup`), and the kernels those features select move scores."""
        import llama_cpp

        features = llama_cpp.llama_print_system_info()
        text = features.decode(errors="replace") if isinstance(features, bytes) else str(features)
        return {"llama_cpp_python": llama_cpp.__version__, "llama_cpp_system_info": " ".join(text.split())}

    # -- tokenization, done once and centrally -------------------------------------------------------
    def token_count(self, text: str) -> int:
        return len(self.encode(text))

    def encode(self, text: str) -> list[int]:
        return self.split.encode(text)

    def context_ids(self, context: str) -> list[int]:
        """The context's tokens, with BOS when the model's metadata asks for it (SmolLM2 does not)."""
        return self.split.context_ids(context)

    # -- scoring --------------------------------------------------------------------------------------
    def _advance_to(self, ids: Sequence[int]) -> NDArray[np.float64]:
        """Hold exactly `ids` in the context; return log p(next token | ids)."""
        if not ids:
            raise ValueError("the context must have at least one token")
        llm = self._llm
        held = llm.input_ids[: llm.n_tokens].tolist()
        if held == list(ids) and self._next_logprobs is not None:
            return self._next_logprobs
        chunks = self._chunks(len(ids))
        reusable = min(common_prefix_length(held, ids), self._canonical, len(ids) - 1)
        keep = max(b for b in chunks[:-1] if b <= reusable)
        llm.n_tokens = keep
        self._next_logprobs = None
        self._next_logprobs = log_softmax(self._eval_last_row(ids, [b for b in chunks if b >= keep]))
        # Full chunks stay reusable; the last one is run again next time (the context will have grown).
        self._canonical = chunks[-2] if len(chunks) > 1 else 0
        return self._next_logprobs

    def _chunks(self, length: int) -> list[int]:
        """The fixed batch layout of a `length`-token context, as boundaries [0, c, 2c, ..., length]; a last
        chunk of one token joins the one before (a one-token batch runs on other kernels, see `_eval_tail`)."""
        size = self.context_chunk
        bounds = [*range(0, length, size), length]
        if len(bounds) > 2 and bounds[-1] - bounds[-2] == 1:
            del bounds[-2]
        return bounds

    def _eval_last_row(self, ids: Sequence[int], bounds: Sequence[int]) -> NDArray[np.float32]:
        """Run `ids[bounds[0]:]` in the batches `bounds` gives (positions in `ids`), asking llama.cpp for the
        last position's logits only.

        With `logits_all=True`, `Llama.eval` computes and copies a vocabulary-sized row for every prompt token,
        which for a 600-token prompt and Qwen's 152k vocabulary is a quarter of the compute and 370 MB of
        copying; only the last row is needed for the context. This uses llama-cpp-python's batch and context
        wrappers (the same calls `Llama.eval` makes) with the logits flag on the last token only.
        """
        llm = self._llm
        self.tokens_evaluated += bounds[-1] - bounds[0]
        llm._ctx.kv_cache_seq_rm(-1, llm.n_tokens, -1)
        for start, end in itertools.pairwise(bounds):
            batch = list(ids[start:end])
            llm._batch.set_batch(batch=batch, n_past=start, logits_all=False)
            llm._ctx.decode(llm._batch)
            llm.input_ids[start:end] = batch
            llm.n_tokens = end
        row = np.ctypeslib.as_array(llm._ctx.get_logits(), shape=(llm.n_vocab(),)).copy()
        llm.scores[llm.n_tokens - 1, :] = row  # the other rows of the context are not read again
        return row

    def _check_fits(self, context_length: int, continuations: Sequence[Sequence[int]]) -> None:
        longest = max((len(c) for c in continuations), default=0)
        if context_length + longest > self._llm.n_ctx():
            raise ValueError(
                f"context ({context_length} tokens) plus the longest continuation ({longest}) exceeds "
                f"n_ctx={self._llm.n_ctx()}: create the model with a larger n_ctx"
            )
        if any(len(c) == 0 for c in continuations):
            raise ValueError("every continuation must have at least one token")

    def score_token_continuations(
        self, context: Sequence[int], continuations: Sequence[Sequence[int]], share_prefixes: bool = True
    ) -> list[float]:
        """Summed log p(continuation | context) per continuation, all given as token ids.

        `share_prefixes=False` runs every candidate's tokens on their own after the context (for comparison).
        """
        self._check_fits(len(context), continuations)
        first = self._advance_to(context)
        llm, prefix = self._llm, len(context)
        scores = [float(first[c[0]]) for c in continuations]
        held: list[int] = []  # candidate tokens currently evaluated after the prefix
        normalizers: dict[int, float] = {}  # log-sum-exp of a row's logits, while the row stays valid
        for index in sorted(range(len(continuations)), key=lambda i: list(continuations[i])):
            continuation = list(continuations[index])
            path = continuation[:-1]
            if not path:
                continue
            common = common_prefix_length(held, path) if share_prefixes else 0
            if common < len(path):
                self._eval_tail(context, path, common)
                held = path
                for row in [r for r in normalizers if r >= prefix + common]:
                    del normalizers[row]
            for j in range(len(path)):
                row = prefix + j
                if row not in normalizers:
                    normalizers[row] = _log_sum_exp(llm.scores[row])
                scores[index] += float(llm.scores[row, continuation[j + 1]]) - normalizers[row]
        llm.n_tokens = prefix  # the candidates are gone; the context stays for the next call
        return scores

    def best_token_continuation(
        self, context: Sequence[int], continuations: Sequence[Sequence[int]]
    ) -> BestContinuation:
        """The continuation with the highest summed log-probability, by branch and bound (exact)."""
        self._check_fits(len(context), continuations)
        first = self._advance_to(context)
        llm, prefix = self._llm, len(context)

        def evaluate(path: Sequence[int], keep: int) -> list[NDArray[np.float64]]:
            self._eval_tail(context, path, keep)
            return [log_softmax(llm.scores[prefix + j]) for j in range(keep, len(path))]

        try:
            return best_continuation(first, continuations, evaluate)
        finally:
            llm.n_tokens = prefix  # the candidates are gone; the context stays for the next call

    def best_continuation(self, context: str, continuations: Sequence[str]) -> BestContinuation:
        """Fast path for SayCan's sum scoring: only the winner, exactly, scoring a fraction of the tokens."""
        return self.best_token_continuation(self.context_ids(context), [self.encode(c) for c in continuations])

    def best_continuations(self, requests: Sequence[ChoiceRequest]) -> list[BestContinuation]:
        """Every in-flight episode's choice; with `sequences` > 1 all of them in shared decodes (the same
        choices as one at a time, to llama.cpp's batch-layout noise: see `llamacpp_sequences`)."""
        if self._sequences is None:
            return super().best_continuations(requests)
        contexts = [self.context_ids(r.context) for r in requests]
        options = [[self.encode(c) for c in r.continuations] for r in requests]
        for context, continuations in zip(contexts, options, strict=True):
            self._check_fits(len(context), continuations)
        return self._sequences.best([r.session for r in requests], contexts, options)

    def submit_choice(self, request: ChoiceRequest) -> None:
        if self._sequences is None:
            super().submit_choice(request)
            return
        context, continuations = self.context_ids(request.context), [self.encode(c) for c in request.continuations]
        self._check_fits(len(context), continuations)
        self._sequences.submit(request.session, context, continuations)

    def advance_choices(self) -> list[tuple[int, BestContinuation]]:
        if self._sequences is None:
            return super().advance_choices()
        return self._sequences.step()

    def end_session(self, session: int) -> None:
        if self._sequences is not None:
            self._sequences.free(session)

    def score_continuations(self, context: str, continuations: Sequence[str]) -> list[float]:
        """Fast path: the context once (over the previous call's shared prefix), then each candidate's tail."""
        return self.score_token_continuations(self.context_ids(context), [self.encode(c) for c in continuations])

    def naive_score_continuations(self, context: str, continuations: Sequence[str]) -> list[float]:
        """Reference path: context + continuation evaluated from scratch for every continuation."""
        context_ids = self.context_ids(context)
        token_continuations = [self.encode(c) for c in continuations]
        self._check_fits(len(context_ids), token_continuations)
        llm, prefix = self._llm, len(context_ids)
        scores = []
        for continuation in token_continuations:
            llm.reset()
            self._eval(context_ids + continuation)
            scores.append(
                sum(float(log_softmax(llm.scores[prefix - 1 + j])[token]) for j, token in enumerate(continuation))
            )
        llm.reset()
        self._next_logprobs = None
        self._canonical = 0
        return scores

    def loglikelihood(self, requests: Sequence[LoglikelihoodRequest]) -> list[float]:
        return loglikelihood_by_context(requests, self.score_continuations)

    # -- generation -----------------------------------------------------------------------------------
    def generate(self, requests: Sequence[GenerateRequest]) -> list[str]:
        outputs = []
        llm = self._generation_context()
        for request in requests:
            # From an empty cache: llama-cpp-python runs the prompt from its longest match with what the cache
            # holds, in its own batches, so the text it generates would depend on the request before (see the
            # module docstring).
            llm.reset()
            options: dict[str, Any] = {
                "max_tokens": request.max_new_tokens,
                "temperature": request.temperature,
                "seed": request.seed,
                "repeat_penalty": 1.0,
                "stop": [s for s in request.stop if s] or None,
            }
            schema = request.schema()
            if self.use_chat_template and request.chat:
                if schema is not None:
                    # llama-cpp-python turns a `json_object` format with a schema into a GBNF grammar that
                    # constrains sampling: the completion is JSON following the schema (or cut at max_tokens).
                    options["response_format"] = {"type": "json_object", "schema": schema}
                response = llm.create_chat_completion(messages=request.messages(), **options)
                text = response["choices"][0]["message"]["content"] or ""
            else:
                if schema is not None:
                    options["grammar"] = _grammar(request.json_schema)
                response = llm.create_completion(request.completion_text(), **options)
                text = response["choices"][0]["text"]
            outputs.append(cut_at_stop(str(text), request.stop).strip())
        return outputs

    def _generation_context(self) -> Any:
        """The context that generates: the same weights and settings as the scoring context, without the
        logits of every position (scoring reads them; sampling needs the last one only)."""
        if self._generator is None:
            from llama_cpp import Llama

            self._generator = Llama(logits_all=False, **self._context_options)
        return self._generator
