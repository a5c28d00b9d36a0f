"""Local transformers causal LMs: a model folder, a model id already on disk, or a GGUF file.

GGUF files are de-quantized by transformers at load (about 20 s for SmolLM2-135M on 2 cores); the
float32 result is kept under the cache folder, keyed by the file's content hash, so later loads take
seconds.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, ClassVar

from talkdem.llm.backends.tokenizing import HFTokenSplit
from talkdem.llm.interface.base import LanguageModel, ModelIdentity, cut_at_stop, file_sha256, loglikelihood_by_context
from talkdem.llm.interface.models import get_model, model_path
from talkdem.llm.interface.options import BackendOption
from talkdem.llm.interface.requests import GenerateRequest, LoglikelihoodRequest
from talkdem.llm.scoring.branch_bound import BestContinuation
from talkdem.paths import cache_dir

if TYPE_CHECKING:
    from talkdem.llm.scoring.prefix_scorer import PrefixCachedScorer

__all__ = ["HFCausalLM"]

_DTYPES = {name: name for name in ("float32", "bfloat16", "float16")}


def _resolve(model: str) -> Path | str:
    spec = get_model(model)
    if spec is not None:
        return model_path(spec.name)
    path = Path(model).expanduser()
    return path if path.exists() else model


class HFCausalLM(LanguageModel):
    """A transformers causal LM on CPU (or `device`), float32 by default for exact scores."""

    options: ClassVar[tuple[BackendOption, ...]] = (
        BackendOption("device", "str", "torch device: cpu, cuda, cuda:1, mps"),
        BackendOption("dtype", "choice", "weights' float type", choices=_DTYPES),
        BackendOption("threads", "int", "CPU threads (torch's default when unset)", minimum=1),
        BackendOption("chat_template", "bool", "wrap generation prompts in the tokenizer's chat template"),
        BackendOption("max_packed_tokens", "int", "tokens of candidates scored in one packed pass", minimum=1),
    )

    def __init__(
        self,
        model: str,
        device: str = "cpu",
        dtype: str = "float32",
        threads: int | None = None,
        chat_template: bool = True,
        max_packed_tokens: int = 2048,
    ) -> None:
        import torch

        from talkdem.llm.scoring.prefix_scorer import (
            PrefixCachedScorer,
        )  # torch's: imported with the model, not the module

        os.environ.setdefault("HF_HUB_OFFLINE", "1")
        if threads:
            torch.set_num_threads(threads)
        torch.manual_seed(0)
        source = _resolve(model)
        self.device = device
        torch_dtype = getattr(torch, dtype)
        if isinstance(source, Path) and source.suffix == ".gguf":
            catalog = get_model(model)
            revision = catalog.sha256 if catalog is not None else file_sha256(source)
            self.model, self.tokenizer = _load_gguf(source, revision, torch_dtype)
        else:
            from transformers import AutoModelForCausalLM, AutoTokenizer

            revision = ""
            self.tokenizer = AutoTokenizer.from_pretrained(str(source))
            self.model = AutoModelForCausalLM.from_pretrained(str(source), dtype=torch_dtype)
        self.model.to(device)
        self.model.eval()
        spec = get_model(model)
        name = spec.name if spec is not None else str(source)
        self.identity = ModelIdentity(backend="hf", name=name, revision=revision)
        self.use_chat_template = chat_template and bool(getattr(self.tokenizer, "chat_template", None))
        self.split = HFTokenSplit(self.tokenizer)
        self.scorer: PrefixCachedScorer = PrefixCachedScorer(self.model, max_packed_tokens=max_packed_tokens)

    def runtime(self) -> dict[str, str]:
        """torch and transformers versions and the device the model runs on."""
        import torch
        import transformers

        return {
            "torch": torch.__version__,
            "transformers": transformers.__version__,
            "device": str(next(self.model.parameters()).device),
        }

    # -- tokenization, done once and centrally -------------------------------------------------------
    def token_count(self, text: str) -> int:
        return len(self.encode(text))

    def encode(self, text: str) -> list[int]:
        return self.split.encode(text)

    def _context_ids(self, context: str) -> list[int]:
        return self.split.context_ids(context)

    # -- the interface --------------------------------------------------------------------------------
    def score_continuations(self, context: str, continuations: Sequence[str]) -> list[float]:
        """Fast path: every continuation of one context in one packed pass over the cached prefix."""
        return self.scorer.score(self._context_ids(context), [self.encode(c) for c in continuations])

    def best_continuation(self, context: str, continuations: Sequence[str]) -> BestContinuation:
        """Fast path for SayCan's sum scoring: only the winner, exactly, by branch and bound."""
        return self.scorer.best(self._context_ids(context), [self.encode(c) for c in continuations])

    def naive_score_continuations(self, context: str, continuations: Sequence[str]) -> list[float]:
        """Reference path: one full forward pass per continuation."""
        from talkdem.llm.scoring.prefix_scorer import naive_scores

        return naive_scores(self.model, self._context_ids(context), [self.encode(c) for c in continuations])

    def loglikelihood(self, requests: Sequence[LoglikelihoodRequest]) -> list[float]:
        return loglikelihood_by_context(requests, self.score_continuations)

    def chat_text(self, request: GenerateRequest) -> str:
        """The request in the tokenizer's chat template, ready for the assistant's answer.

        Some templates refuse a system role (Gemma's raise an error); the system message then leads the user's.
        """
        try:
            text = self.tokenizer.apply_chat_template(request.messages(), tokenize=False, add_generation_prompt=True)
        except Exception as error:  # jinja2's TemplateError, raised by the template itself
            if not request.system or "system" not in str(error).lower():
                raise
            merged = [{"role": "user", "content": request.completion_text()}]
            text = self.tokenizer.apply_chat_template(merged, tokenize=False, add_generation_prompt=True)
        return str(text)

    def generate(self, requests: Sequence[GenerateRequest]) -> list[str]:
        """Greedy or seeded-sampled completions. transformers has no constrained decoding of its own, so a
        request's `json_schema` is not enforced here (`supports_json_schema` is False): the model writes free
        text, and a caller that wants JSON must ask for it in the prompt and parse it."""
        import torch

        outputs = []
        for request in requests:
            if self.use_chat_template and request.chat:
                ids = self.encode(self.chat_text(request))
            else:
                ids = self._context_ids(request.completion_text())
            sampling: dict[str, Any] = {"do_sample": False}
            if request.temperature > 0:
                torch.manual_seed(request.seed)  # HF samples from torch's global generator
                sampling = {"do_sample": True, "temperature": request.temperature, "top_k": 0, "top_p": 1.0}
            with torch.no_grad():
                generated = self.model.generate(
                    input_ids=torch.tensor([ids], device=self.device),
                    attention_mask=torch.ones(1, len(ids), dtype=torch.long, device=self.device),
                    max_new_tokens=request.max_new_tokens,
                    **sampling,
                    pad_token_id=self.tokenizer.eos_token_id,
                )
            text_out = self.tokenizer.decode(generated[0, len(ids) :], skip_special_tokens=True)
            outputs.append(cut_at_stop(text_out, request.stop).strip())
        return outputs


def _load_gguf(path: Path, revision: str, torch_dtype: Any) -> tuple[Any, Any]:
    from transformers import AutoModelForCausalLM, AutoTokenizer

    converted = cache_dir() / "hf-from-gguf" / f"{path.stem}-{revision[:16]}"
    if (converted / "config.json").is_file():
        return (
            AutoModelForCausalLM.from_pretrained(str(converted), dtype=torch_dtype),
            AutoTokenizer.from_pretrained(str(converted)),
        )
    tokenizer = AutoTokenizer.from_pretrained(str(path.parent), gguf_file=path.name)
    model: Any = AutoModelForCausalLM.from_pretrained(str(path.parent), gguf_file=path.name, dtype=torch_dtype)
    # transformers refuses to save a model it still marks as GGUF-quantized; the weights are plain tensors
    # after de-quantization, so drop the marker and save them.
    model.hf_quantizer = None
    if hasattr(model.config, "quantization_config"):
        del model.config.quantization_config
    partial = converted.with_name(converted.name + ".partial")
    model.save_pretrained(str(partial))
    tokenizer.save_pretrained(str(partial))
    partial.rename(converted)  # atomic: a killed conversion never leaves a half-written cache
    return model, tokenizer
