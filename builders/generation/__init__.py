"""The generation that needs a language model: the `llm` generator (the paper's prompts on a backend) and the
ranking of verified candidates.

The rule-based generators (`rules`, i.e. `rules-v3`) are runtime code in `talkdem.speech`, whose registry
knows only them; importing this package registers `llm` there, so a dataset-building command that imports the
builders can ask `talkdem.speech.get_generator` for it, and the library never reaches a model through it.
"""

from talkdem.speech.base import Generator, register_generator

__all__: list[str] = []


def _default_llm_generator() -> Generator:
    """The paper's prompts on the embedded default model (SmolLM2-135M through transformers)."""
    from builders.generation.llm import LLMGenerator
    from talkdem.llm.interface.registry import load_model

    return LLMGenerator(load_model("hf", "smollm2-135m-instruct"))


register_generator("llm", _default_llm_generator)
