"""vLLM's offline engine (GPU users): log-likelihoods from prompt logprobs, batched generation.

NOT TESTED IN THIS PROJECT: our machines have no GPU and vLLM is not installed. The unit tests cover only
what runs without vLLM (the clear error when it is missing, and the pure request planning and logprob
summing below). `vllm` is imported only when a `VLLMLM` is created.

Sharing is done here, not by vLLM: requests that ask for prompt logprobs bypass vLLM's prefix cache, and
prefix caching has been reported to make prompt logprobs nondeterministic, so the engine is started with
`enable_prefix_caching=False`. Each context is tokenized once; identical (context, continuation) pairs and
continuations whose tokens are a prefix of another continuation of the same context are answered from one
sequence's prompt logprobs; all remaining sequences go to the engine in one batched call.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any, ClassVar

from talkdem.llm.backends.tokenizing import HFTokenSplit
from talkdem.llm.interface.base import LanguageModel, ModelIdentity, cut_at_stop
from talkdem.llm.interface.options import BackendOption
from talkdem.llm.interface.requests import GenerateRequest, LoglikelihoodRequest

__all__ = ["VLLMLM", "ScoringPlan", "guided_json_options", "plan_scoring", "sum_prompt_logprobs"]

_MISSING = "vLLM is not installed: install it on a machine with a GPU (`pip install vllm`, see docs.vllm.ai)"


@dataclass(frozen=True)
class ScoringPlan:
    """Which token sequences to send, and where each request's continuation lies in one of them."""

    sequences: list[list[int]]
    spans: list[tuple[int, int, int]]
    """Per request: (sequence index, first continuation position, end position)."""


def plan_scoring(
    requests: Sequence[LoglikelihoodRequest],
    encode_context: Callable[[str], list[int]],
    encode_continuation: Callable[[str], list[int]],
) -> ScoringPlan:
    """Tokenize each context once; a continuation that is a token prefix of another one rides along with it."""
    context_ids: dict[str, list[int]] = {}
    per_request: list[tuple[str, tuple[int, ...]]] = []
    for request in requests:
        if request.context not in context_ids:
            context_ids[request.context] = encode_context(request.context)
        continuation = tuple(encode_continuation(request.continuation))
        if not continuation:
            raise ValueError(f"empty continuation {request.continuation!r}: nothing to score")
        if not context_ids[request.context]:
            raise ValueError("the context must have at least one token")
        per_request.append((request.context, continuation))
    # For each context, keep the continuations that are not a strict prefix of another one.
    carriers: dict[tuple[str, tuple[int, ...]], int] = {}
    sequences: list[list[int]] = []
    by_context: dict[str, list[tuple[int, ...]]] = {}
    for context, continuation in per_request:
        by_context.setdefault(context, []).append(continuation)
    for context, continuations in by_context.items():
        ordered = sorted(set(continuations), key=lambda c: (-len(c), c))
        for continuation in ordered:
            carrier = next(
                (c for c in ordered if len(c) > len(continuation) and c[: len(continuation)] == continuation), None
            )
            if carrier is None:
                carriers[(context, continuation)] = len(sequences)
                sequences.append(context_ids[context] + list(continuation))
            else:
                carriers[(context, continuation)] = carriers[(context, carrier)]
    spans = []
    for context, continuation in per_request:
        start = len(context_ids[context])
        spans.append((carriers[(context, continuation)], start, start + len(continuation)))
    return ScoringPlan(sequences, spans)


def sum_prompt_logprobs(
    prompt_logprobs: Sequence[Mapping[int, Any] | None], token_ids: Sequence[int], start: int, end: int
) -> float:
    """Sum of log p(token_ids[i] | token_ids[:i]) for i in [start, end), from vLLM's `prompt_logprobs`.

    vLLM gives, per prompt position, a dict from token id to a `Logprob` (with `.logprob`) that always holds
    the actual prompt token; position 0 has none.
    """
    total = 0.0
    for position in range(start, end):
        entry = prompt_logprobs[position]
        if entry is None or token_ids[position] not in entry:
            raise ValueError(f"no prompt logprob for position {position}")
        value = entry[token_ids[position]]
        total += float(getattr(value, "logprob", value))
    return total


class VLLMLM(LanguageModel):
    """A model served by vLLM's offline `LLM` engine in this process (one or more GPUs).

    Generation applies the model's chat template (system and user messages) and constrains decoding to a
    request's JSON schema by vLLM's structured outputs (`supports_json_schema`).

    `engine_options` go to `vllm.LLM` unchanged (e.g. `max_model_len`, `quantization`); of them, those two may be
    set by name (`options`), the others only by a caller constructing the backend.
    """

    supports_json_schema = True
    options: ClassVar[tuple[BackendOption, ...]] = (
        BackendOption("tensor_parallel_size", "int", "GPUs the model is split over", minimum=1),
        BackendOption("dtype", "str", "weights' type as vLLM names it (auto, bfloat16, float16, float32)"),
        BackendOption(
            "gpu_memory_utilization", "float", "share of GPU memory the engine may take", minimum=0, above_minimum=True
        ),
        BackendOption("seed", "int", "the engine's seed", minimum=0),
        BackendOption("chat_template", "bool", "wrap generation prompts in the model's chat template"),
        BackendOption("revision", "str", "the hub revision of the model"),
        BackendOption("max_model_len", "int", "context length in tokens (an engine option)", minimum=1),
        BackendOption("quantization", "str", "the weights' quantization method (an engine option)"),
    )

    def __init__(
        self,
        model: str,
        tensor_parallel_size: int = 1,
        dtype: str = "auto",
        gpu_memory_utilization: float = 0.9,
        seed: int = 0,
        chat_template: bool = True,
        revision: str | None = None,
        **engine_options: Any,
    ) -> None:
        try:
            import vllm
        except ImportError as error:
            raise ImportError(_MISSING) from error
        engine_options.setdefault("enable_prefix_caching", False)
        self._llm = vllm.LLM(
            model=model,
            tensor_parallel_size=tensor_parallel_size,
            dtype=dtype,
            gpu_memory_utilization=gpu_memory_utilization,
            seed=seed,
            revision=revision,
            **engine_options,
        )
        self._vllm = vllm
        self.tokenizer = self._llm.get_tokenizer()
        self.use_chat_template = chat_template and bool(getattr(self.tokenizer, "chat_template", None))
        self.split = HFTokenSplit(self.tokenizer)
        self.identity = ModelIdentity(backend="vllm", name=model, revision=revision or "")

    def runtime(self) -> dict[str, str]:
        return {"vllm": str(getattr(self._vllm, "__version__", ""))}

    def token_count(self, text: str) -> int:
        return len(self.encode(text))

    def encode(self, text: str) -> list[int]:
        return self.split.encode(text)

    def _context_ids(self, context: str) -> list[int]:
        return self.split.context_ids(context)

    def score_continuations(self, context: str, continuations: Sequence[str]) -> list[float]:
        return self.loglikelihood([LoglikelihoodRequest(context, c) for c in continuations])

    def loglikelihood(self, requests: Sequence[LoglikelihoodRequest]) -> list[float]:
        if not requests:
            return []
        plan = plan_scoring(requests, self._context_ids, self.encode)
        params = self._vllm.SamplingParams(max_tokens=1, temperature=0.0, prompt_logprobs=0)
        prompts = [{"prompt_token_ids": ids} for ids in plan.sequences]
        outputs = self._llm.generate(prompts, params, use_tqdm=False)
        return [
            sum_prompt_logprobs(outputs[index].prompt_logprobs, plan.sequences[index], start, end)
            for index, start, end in plan.spans
        ]

    def generate(self, requests: Sequence[GenerateRequest]) -> list[str]:
        """Chat requests through `LLM.chat` (the model's template, system and user messages), plain completions
        through `LLM.generate`; a request's `json_schema` becomes vLLM's guided (structured) decoding."""
        if not requests:
            return []
        params = [self._sampling_params(r) for r in requests]
        chat = [i for i, r in enumerate(requests) if self.use_chat_template and r.chat]
        plain = [i for i, r in enumerate(requests) if not (self.use_chat_template and r.chat)]
        texts: dict[int, str] = {}
        if chat:
            conversations = [requests[i].messages() for i in chat]
            outputs = self._llm.chat(conversations, [params[i] for i in chat], use_tqdm=False)
            texts.update((i, o.outputs[0].text) for i, o in zip(chat, outputs, strict=True))
        if plain:
            prompts = [requests[i].completion_text() for i in plain]
            outputs = self._llm.generate(prompts, [params[i] for i in plain], use_tqdm=False)
            texts.update((i, o.outputs[0].text) for i, o in zip(plain, outputs, strict=True))
        return [cut_at_stop(texts[i], r.stop).strip() for i, r in enumerate(requests)]

    def _sampling_params(self, request: GenerateRequest) -> Any:
        options: dict[str, Any] = {
            "temperature": request.temperature,
            "seed": request.seed if request.temperature > 0 else None,
            "max_tokens": request.max_new_tokens,
            "stop": [s for s in request.stop if s],
        }
        schema = request.schema()
        if schema is not None:
            options.update(guided_json_options(self._vllm, schema))
        return self._vllm.SamplingParams(**options)


def guided_json_options(vllm: Any, schema: dict[str, Any]) -> dict[str, Any]:
    """SamplingParams keywords constraining the output to `schema`: vLLM 0.11 and later name them
    `structured_outputs=StructuredOutputsParams(json=...)`, earlier releases `guided_decoding=GuidedDecodingParams`."""
    sampling = vllm.sampling_params
    if hasattr(sampling, "StructuredOutputsParams"):
        return {"structured_outputs": sampling.StructuredOutputsParams(json=schema)}
    if hasattr(sampling, "GuidedDecodingParams"):
        return {"guided_decoding": sampling.GuidedDecodingParams(json=schema)}
    raise ImportError(f"this vLLM ({getattr(vllm, '__version__', '?')}) has no structured outputs for a JSON schema")
