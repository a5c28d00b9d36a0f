"""Validation the generator never sees: the paper's markers as the literature defines them, fluency, variety.

Nothing here imports the generator and its lexicon (`talkdem.speech`), `builders.generation`,
`builders.verification` or `builders.markers`, and the generator imports nothing from here (a test checks
both), so the figures cannot be met by matching the generator's own cue lists.
"""

from builders.validation.card import validation_markdown, validation_section
from builders.validation.report import run_validation

__all__ = ["run_validation", "validation_markdown", "validation_section"]
