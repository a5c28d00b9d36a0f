"""Published word inventories behind the independent markers, each with its source.

Nothing here is taken from the generator's phrase banks or the verifier's cue lists: every list is a
published inventory (or the closed-class items a cited definition names), so a generator cannot pass
these measures by inserting its own cues. Where a list had to be narrowed or widened the reason and the
source are given beside it.
"""

from __future__ import annotations

__all__ = [
    "CONNECTIVE_MARKERS",
    "EDITING_PHRASES",
    "EDITING_WORDS",
    "FILLED_PAUSES",
    "GENERAL_NOUNS",
    "NON_DISCOURSE_INTERJECTIONS",
    "PHRASAL_MARKERS",
    "PLACEHOLDER_NOUNS",
]

GENERAL_NOUNS = frozenset(
    {
        # Halliday & Hasan (1976), Cohesion in English, section 6.2 ("general nouns"), their classes:
        # human, non-human animate, inanimate concrete count and mass, inanimate abstract, action, place, fact.
        "people",
        "person",
        "man",
        "woman",
        "child",
        "boy",
        "girl",
        "creature",
        "thing",
        "object",
        "stuff",
        "business",
        "affair",
        "matter",
        "move",
        "place",
        "question",
        "idea",
        "fact",
    }
)
"""Halliday & Hasan's general nouns (singular; plurals are matched through spaCy's lemma)."""

PLACEHOLDER_NOUNS = frozenset(
    {
        # Placeholder ("what-d'you-call-it") words, the recognitional-deixis forms discussed by Enfield (2003),
        # "The definition of what-d'you-call-it", Journal of Pragmatics 35, 101-117, in their common spellings.
        "thingy",
        "thingamajig",
        "thingamabob",
        "thingummy",
        "thingummyjig",
        "whatsit",
        "whatchamacallit",
        "whatsitsname",
        "doodah",
        "doodad",
        "gizmo",
    }
)
"""Placeholder nouns; with the general nouns these are the vague nominals beside pronouns."""

FILLED_PAUSES = frozenset({"um", "uh", "er", "erm", "ah", "hmm", "mm", "uhm", "eh"})
"""Filled pauses (Clark & Fox Tree 2002, "Using uh and um in spontaneous speaking", Cognition 84, 73-111)."""

PHRASAL_MARKERS: tuple[tuple[str, ...], ...] = (
    # Schiffrin (1987), Discourse Markers, chapters 9-10: "y'know" and "I mean" are markers wherever they stand.
    ("you", "know"),
    ("y'know",),
    ("i", "mean"),
    # Fraser (2009), "Topic orientation markers", Journal of Pragmatics 41, 892-898: topic-change markers.
    ("by", "the", "way"),
    ("anyway",),
    ("anyhow",),
    ("incidentally",),
)
"""Markers counted wherever they occur (token sequences, lowercased)."""

CONNECTIVE_MARKERS = frozenset(
    {
        # Schiffrin (1987): oh, well, and, but, or, so, because, now, then (I mean, y'know above).
        "oh",
        "well",
        "and",
        "but",
        "or",
        "so",
        "because",
        "now",
        "then",
        # Fraser (1999), "What are discourse markers?", Journal of Pragmatics 31, 931-952: contrastive,
        # elaborative and inferential markers that open a segment.
        "however",
        "although",
        "also",
        "besides",
        "furthermore",
        "moreover",
        "therefore",
        "thus",
        "anyway",
        "still",
        "instead",
        "otherwise",
    }
)
"""Markers that are also ordinary words ("put it in and close it", "as well"): counted only in the left
periphery of a sentence (Schiffrin's utterance-initial position; Fraser's segment-initial S2 position),
i.e. when nothing but other markers and punctuation precedes them in their sentence."""

NON_DISCOURSE_INTERJECTIONS = frozenset(
    {
        # Fraser (1996), "Pragmatic markers", Pragmatics 6, 167-190, puts politeness markers (please, kindly)
        # among the parallel pragmatic markers, not the discourse markers; greetings, leave-takings and
        # thanks are speech-act formulae, and yes/no answer particles carry propositional content. spaCy tags
        # all of these INTJ, so they are removed from the parse-based count.
        "please",
        "kindly",
        "hi",
        "hello",
        "hey",
        "bye",
        "goodbye",
        "thanks",
        "thank",
        "cheers",
        "yes",
        "yeah",
        "yep",
        "no",
        "nope",
    }
)

EDITING_WORDS = frozenset({"sorry", "rather", "no", "oops"})
"""One-word editing terms of self-repair: Levelt (1983), "Monitoring and self-repair in speech", Cognition 14,
41-104 (sorry, rather, no) and Schegloff, Jefferson & Sacks (1977), "The preference for self-correction",
Language 53, 361-382 (oops among the repair initiators). "no" counts only where spaCy parses it as an
interjection (the editing term), never as a determiner ("no milk")."""

EDITING_PHRASES: tuple[tuple[str, ...], ...] = (
    # Levelt (1983): "I mean", "or rather"; "I meant" is the past-tense form of the same term. His "that is"
    # is left out: in instructions it is mostly the ordinary clause ("that is where I left it").
    ("i", "mean"),
    ("i", "meant"),
    ("or", "rather"),
)
"""Multi-word editing terms (token sequences, lowercased)."""
