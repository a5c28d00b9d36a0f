"""The in-pattern speaker: the rule-based generator and everything it speaks with, as runtime code.

The dataset is built with it (`builders/` imports it), and the clarification track's simulated person answers
with it at run time (`talkdem.clarify.person`), so it lives in the library, which never imports the builders.
What is here: the generator interface and registry (`base`), `rules-v3` (`rules_v3`, its phrase tables
`phrases_v3`, the clean control it keeps from `rules-v2` in `clean_control`), the utterance forms (`forms`), the
speakers (`personas`), the typed object lexicon (`object_kinds`), the object-space lexicon (`lexicon`), a seed's
task terms (`task_terms`) and the cue lists the verifier looks for (`cues`).
"""

from talkdem.speech.base import (
    CLEAN,
    GenerationRequest,
    Generator,
    check_generator_name,
    derive_seed,
    get_generator,
    register_generator,
)

__all__ = [
    "CLEAN",
    "GenerationRequest",
    "Generator",
    "check_generator_name",
    "derive_seed",
    "get_generator",
    "register_generator",
]
