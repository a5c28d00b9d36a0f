"""CARE: Context-Aware Retrieval from Experience (paper, section "Context-Aware Retrieval from Experience").

For each instruction, the k=3 memory items whose instructions are most cosine-similar (all-MiniLM-L6-v2)
are inserted into the planner prompt as demonstrations: instruction, one-sentence interpretation from the
gold task specification, reference plan.

Two choices the paper leaves open are options (docs/strategies.md): `order` (`best_last`, the default: the
most similar item sits next to the query; `best_first`: as retrieved) and `dedupe` (keep only the most
similar item of each memory task, so the k items come from k tasks; off by default, the paper's "k items
with the highest similarity").
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Literal, get_args

import numpy as np

from care.embedding_cache import CachedEncoder
from care.memory import Encoder, memory_embeddings
from care.retrieval import top_k
from talkdem.embeddings import ENCODER_NAME
from talkdem.instructions import MemoryItem, load_memory_bank
from talkdem.llm.interface.base import LanguageModel
from talkdem.llm.interface.options import BackendOption
from talkdem.planner.prompt import Demonstration, prompt_text
from talkdem.planner.strategies import PlannerInput, Strategy

__all__ = ["ContextAwareRetrieval", "Order"]

Order = Literal["best_first", "best_last"]


def _minilm() -> Encoder:
    from talkdem.embeddings import encode  # torch loads only when CARE is used

    return encode


class ContextAwareRetrieval(Strategy):
    name = "care"
    arguments = (
        BackendOption("order", "choice", "where the most similar item goes", choices={o: o for o in get_args(Order)}),
        BackendOption("dedupe", "bool", "at most one retrieved item per memory task"),
    )

    def __init__(
        self,
        memory: Sequence[MemoryItem] | None = None,
        k: int = 3,
        encode: Encoder | None = None,
        order: Order = "best_last",
        dedupe: bool = False,
    ) -> None:
        if order not in get_args(Order):
            raise ValueError(f"CARE order must be one of {', '.join(get_args(Order))}, got {order!r}")
        self.memory = tuple(memory if memory is not None else load_memory_bank())
        self.k = k
        self.order: Order = order
        self.dedupe = dedupe
        # The default encoder's embeddings are cached on disk by (text, encoder): a repeated run over the same
        # instructions encodes nothing. An encoder passed in has no name to key a cache by, so neither its
        # queries nor the memory's embeddings touch the disk (keyed by MiniLM's name they would poison its cache).
        if encode is None:
            self.encode: Encoder = CachedEncoder(_minilm(), ENCODER_NAME)
            self.embeddings = memory_embeddings(self.memory, self.encode, ENCODER_NAME)
        else:
            self.encode = encode
            self.embeddings = np.asarray(encode([item.instruction for item in self.memory]), dtype=np.float64)

    def options(self) -> dict[str, object]:
        return {"k": self.k, "order": self.order, "dedupe": self.dedupe}

    def retrieve(self, instructions: Sequence[str]) -> list[list[MemoryItem]]:
        """The k items per instruction, best first (with `dedupe`, at most one per memory task)."""
        queries = self.encode(list(instructions))
        if not self.dedupe:
            return [[self.memory[i] for i in row] for row in top_k(queries, self.embeddings, self.k)]
        # Every memory task has 16 items; ranking them all and keeping each task's first is exact.
        ranked = top_k(queries, self.embeddings, len(self.memory))
        chosen = []
        for row in ranked:
            items: list[MemoryItem] = []
            seen: set[str] = set()
            for index in row:
                item = self.memory[index]
                if item.task_id not in seen:
                    seen.add(item.task_id)
                    items.append(item)
                    if len(items) == self.k:
                        break
            chosen.append(items)
        return chosen

    def prepare(self, instructions: Sequence[str], model: LanguageModel) -> list[PlannerInput]:
        intro = prompt_text("demonstrations_intro")
        inputs = []
        for instruction, items in zip(instructions, self.retrieve(instructions), strict=True):
            shown = items[::-1] if self.order == "best_last" else items
            demos = tuple(Demonstration(m.instruction, m.reference_plan, m.interpretation) for m in shown)
            inputs.append(
                PlannerInput(
                    instruction,
                    demonstrations=demos,
                    demonstrations_intro=intro,
                    notes={"retrieved": ",".join(m.id for m in items)},
                )
            )
        return inputs
