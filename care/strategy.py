"""CARE: Context-Aware Retrieval from Experience (paper, section "Context-Aware Retrieval from Experience").

For each instruction, the k=3 memory items whose instructions are most cosine-similar (all-MiniLM-L6-v2)
are inserted into the planner prompt as demonstrations: instruction, one-sentence interpretation from the
gold task specification, reference plan.
"""

from __future__ import annotations

from collections.abc import Sequence

from care.embedding_cache import CachedEncoder
from care.memory import Encoder, memory_embeddings
from care.retrieval import top_k
from talkdem.embeddings import ENCODER_NAME
from talkdem.instructions import MemoryItem, load_memory_bank
from talkdem.llm.base import LanguageModel
from talkdem.planner.prompt import Demonstration, prompt_text
from talkdem.planner.strategies import PlannerInput, Strategy

__all__ = ["ContextAwareRetrieval"]


def _minilm() -> Encoder:
    from talkdem.embeddings import encode  # torch loads only when CARE is used

    return encode


class ContextAwareRetrieval(Strategy):
    name = "care"

    def __init__(self, memory: Sequence[MemoryItem] | None = None, k: int = 3, encode: Encoder | None = None) -> None:
        self.memory = tuple(memory if memory is not None else load_memory_bank())
        self.k = k
        # The default encoder's embeddings are cached on disk by (text, encoder): a repeated run over the same
        # instructions encodes nothing. An encoder passed in has no name to key a cache by, so it is used as is.
        if encode is None:
            self.encode: Encoder = CachedEncoder(_minilm(), ENCODER_NAME)
            self.embeddings = memory_embeddings(self.memory, self.encode, ENCODER_NAME)
        else:
            # Never on disk under MiniLM's name: another encoder's vectors there would poison every later run.
            self.encode = encode
            self.embeddings = encode([item.instruction for item in self.memory])

    def retrieve(self, instructions: Sequence[str]) -> list[list[MemoryItem]]:
        queries = self.encode(list(instructions))
        return [[self.memory[i] for i in row] for row in top_k(queries, self.embeddings, self.k)]

    def prepare(self, instructions: Sequence[str], model: LanguageModel) -> list[PlannerInput]:
        intro = prompt_text("demonstrations_intro")
        inputs = []
        for instruction, items in zip(instructions, self.retrieve(instructions), strict=True):
            demos = tuple(Demonstration(m.instruction, m.reference_plan, m.interpretation) for m in items)
            inputs.append(
                PlannerInput(
                    instruction,
                    demonstrations=demos,
                    demonstrations_intro=intro,
                    notes={"retrieved": ",".join(m.id for m in items)},
                )
            )
        return inputs
