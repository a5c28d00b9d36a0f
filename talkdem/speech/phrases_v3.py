"""Phrase parts of the `rules-v3` generator: composed per utterance, filled from the speaker's persona.

Rules every part keeps (the tests check them on every part with every fill):
- no object name (objects come only through typed slots), no state word (hot, cold, clean, ...), no task verb
  (put, take, turn, see, ...), no dash or colon;
- nothing asks for anything: no "could you", "please", "ought to", "don't forget", no second errand;
- one older speaker: the same person's family, work and places (`personas.py`) in every part.

Slots: `{x_the}`, `{x_a}`, `{x_it}`, `{x_is}`, ... name a scene object (see `object_kinds.Noun.slots`), `{t_...}`
a task object; `{spouse_name}`, `{child}`, `{workplace}`, ... come from the persona.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Frame", "frames"]

VERSION = "rules-v3"


@dataclass(frozen=True)
class Frame:
    """A sentence with object slots and the kinds of thing each slot can take."""

    text: str
    x: frozenset[str]
    """Kinds the scene object `{x_...}` may be (empty: the frame names no scene object)."""
    t: frozenset[str] = frozenset()
    """Kinds the task object `{t_...}` may be (empty: the frame names none)."""
    late: bool | None = None
    """Only for a speaker whose spouse has died (True), is alive (False), or either (None)."""


def frames(*rows: tuple[str, str] | tuple[str, str, str] | tuple[str, str, str, bool]) -> tuple[Frame, ...]:
    """Frames from rows (x kinds, text[, t kinds[, late]]); kinds are space-separated, "" for none."""
    out = []
    for row in rows:
        x, text = row[0], row[1]
        t = row[2] if len(row) > 2 else ""
        late = row[3] if len(row) > 3 else None
        out.append(Frame(text, frozenset(str(x).split()), frozenset(str(t).split()), late))
    return tuple(out)


ANY_MOVABLE = "food cutlery crockery cookware keepsake gadget pocket reading textile toiletry bottle sport plant"
HOUSEHOLD = "keepsake crockery cookware lamp picture seat table storage appliance plant textile reading gadget"
GIFTS = "keepsake crockery cookware lamp picture textile"  # no gadget: nobody gave a phone as a wedding present
# Things that last for years and stay put or get kept (no food, no fixture): "lasted longer than the house".
DURABLE = "keepsake crockery cookware cutlery lamp picture seat table storage appliance textile reading gadget pocket"
# Things one keeps beside another thing (portable, not food): "kept {t_the} right by {x_the}".
PORTABLE = "keepsake crockery cookware cutlery gadget pocket reading textile toiletry bottle sport plant"
# Furniture a pet sleeps between or a room is arranged around.
FURNITURE = "seat table storage lamp appliance"

# --- Referential Imprecision ---------------------------------------------------------------------------------
VAGUE_SINGULAR = ("thing", "thingy", "whatsit", "whatchamacallit", "thingamajig", "doodad", "thingamabob", "gizmo")
VAGUE_PLURAL = ("things", "stuff")
# Between the vague word and the name at Level 1 (each keeps the name within the phrase).
HESITATIONS = ("oh", "um", "er", "you know", "I mean", "erm", "ah", "uh", "no", "well")
# Level 1: a remark on forgetting after the request (no object, no request).
FORGETTING = (
    "My memory these days.",
    "Names go first, don't they.",
    "I'm worse with names every year.",
    "{Spouse_name} used to tease me about that.",
    "Words just slip away now.",
    "Honestly, my head.",
    "It's the names I lose.",
    "I had it on the tip of my tongue.",
    "Silly me.",
    "{Child_name} says I'm forgetful now.",
    "Dear me, my brain.",
    "That word always escapes me.",
    "I knew it all along, really.",
    "It's these tablets, I'm sure.",
    "Goodness, the names.",
    "It comes and goes.",
)
# Level 2: the name after the request, composed lead + core + tag.
NAME_LEADS = ("", "", "Oh, ", "I mean ", "Sorry, ", "Ah, ", "Yes, ", "Now, ", "Well, ", "Um, ", "Right, ")
NAME_CORES = (
    "{name}",
    "{name}, that's what I mean",
    "it's {name} I'm after",
    "{name}, that's the word",
    "I'm talking about {name}",
    "{name}, I should have said",
    "I meant {name}",
    "{name} {name_is} what I meant",
    "{name}, that's what it's called",
    "{name}, if I'd said it right",
    "{name}, of course",
    "{name}, I couldn't think of it",
    "{name}, it's come to me",
    "{name}, that's the name",
    "{name}, bless me",
)
NAME_TAGS = ("", "", "", ", of course", ", yes", ", dear", ", silly me", ", obviously", ", love", ", there")
# After the request sentence, as a tag instead of a sentence.
NAME_AFTERTHOUGHTS = ("{name} I mean", "{name}, that is", "or {name}, I should say", "{name}, I'm thinking of")
# Word-finding trouble: lead + search, and a whole search sentence.
SEARCH_LEADS = ("Oh", "Now", "Hmm", "Well", "Ah", "Um", "Uh", "Er", "Goodness", "Dear me", "Oh dear", "Honestly")
SEARCHES = (
    "what is it",
    "what's it called",
    "I know it",
    "it's gone",
    "where has it gone",
    "it won't come",
    "what do I call it",
    "I've lost it",
    "it's slipped away",
    "how do I say it",
    "I know this",
    "what was it",
    "it's coming",
    "the word's gone",
    "it's on the tip of my tongue",
    "give me a minute",
    "I had it just now",
    "it's right there",
)
SEARCH_SENTENCES = (
    "It'll come to me.",
    "I can't think of it.",
    "You know the one I mean.",
    "I had it a minute ago.",
    "It's gone right out of my head.",
    "I use it every day.",
    "You'd know it if you spotted it.",
    "{Spouse_name} would know the word.",
    "{Child_name} is always telling me the name.",
    "I should know this.",
    "It starts with, oh, I don't know.",
    "I'm hopeless with names now.",
    "It's on the tip of my tongue.",
    "I'll think of it in a minute.",
    "What do they call it.",
    "You've seen me with it.",
    "My mind's gone blank.",
    "It's there, and then it's gone.",
    "I knew it this morning.",
    "Oh, what's the word.",
)
# Level 2: a remark before the name that names people rather than "I" and "it" (the paper's Level 2 pronoun
# share, 0.308, sits well below its Level 3, 0.351).
SEARCH_NAMED = (
    "{Spouse_name} would know the word.",
    "{Child_name} always knows the names.",
    "{Grandchild_name} laughs at me for this.",
    "{Sibling_name} has the same trouble.",
    "Names were never my strong point.",
    "My mother was the same with names.",
    "Names, names.",
    "{Colleague} used to tease me about names.",
    "Oh, the name.",
    "The word, the word.",
)
FINAL_NAMINGS = (
    "{Name}. Yes, {name}.",
    "{Name}, that's it.",
    "{Name}, of course.",
    "{Name}, that's the one.",
    "Aha, {name}. Yes.",
    "Yes, {name}.",
    "{Name}, finally.",
    "Of course, {name}.",
    "There, {name}.",
    "{Name}, I knew it.",
    "That's it, {name}.",
    "{Name}, it came back.",
    "Got it, {name}.",
    "{Name}, goodness me.",
    "{Name}, that's what it is.",
)
SECOND_VAGUE = ("that one", "the one there", "this one", "that thing", "the one I mean", "you know the one")
# Descriptions by kind (by look, feel, where it is kept or whose it is; never by what one cooks or cleans with).
DESCRIPTIONS: dict[str, tuple[str, ...]] = {
    "food": (
        "the one from the market",
        "the one {grandchild_name} likes",
        "the one in the bag from the shop",
        "the one {spouse_name} always bought",
        "the one we had with our tea",
    ),
    "cutlery": (
        "the one from the good cutlery",
        "the one with the wooden handle",
        "the shiny one",
        "the one {spouse_name} liked best",
        "the one we had as a wedding present",
        "the one my mother left me",
    ),
    "crockery": (
        "the one with the blue rim",
        "the one with the flowers on",
        "the one {spouse_name} always used",
        "the one from the good dinner service",
        "the one {grandchild_name} painted",
        "the one with the chip in it",
        "the white one",
    ),
    "cookware": (
        "the heavy one with the handle",
        "the big one",
        "the old one of my mother's",
        "the one with the lid",
        "the one {spouse_name} bought in {hometown}",
    ),
    "keepsake": (
        "the one {sibling_name} gave me",
        "the one from {hometown}",
        "the one we had for our anniversary",
        "the little one {grandchild_name} likes",
        "the one that was my mother's",
        "the one from {holiday}",
    ),
    "gadget": (
        "the one {child_name} gave me",
        "the one {grandchild_name} sorted out for me",
        "the new one",
        "the one I can never work",
        "the one {grandchild_name} fiddles with",
    ),
    "pocket": (
        "the one I'm always losing",
        "the little one that goes in my handbag",
        "the one I had in my coat",
        "the one {child_name} gave me",
        "the one that's never where I left it",
    ),
    "reading": (
        "the one I was reading",
        "the one {friend_name} lent me",
        "the one with the crossword",
        "the one I keep by me",
        "the one with the big print",
    ),
    "textile": (
        "the soft one",
        "the one {sibling_name} gave us",
        "the one with the stripes",
        "the blue one",
        "the one from the linen press",
    ),
    "toiletry": (
        "the one from the bathroom",
        "the one that smells of lavender",
        "the one {child_name} bought",
        "the one from the shop on the corner",
        "the white one",
    ),
    "bottle": (
        "the glass one",
        "the one on the side",
        "the one with the label",
        "the one {spouse_name} liked",
        "the tall one",
    ),
    "sport": (
        "the one {grandchild_name} plays with",
        "{child_name}'s old one",
        "the one from the garden",
        "the one {child_name} had as a child",
    ),
    "plant": ("the one {friend_name} gave me", "the one by the door", "the one I like best", "the one from the garden"),
    "storage": ("the brown one", "the one we keep odds and ends in", "the big one", "the one from the loft"),
    "appliance": (
        "the one {spouse_name} bought",
        "the one we've had for years",
        "the one in the corner",
        "the old one",
    ),
}
GENERIC_DESCRIPTIONS = ("the one I always use", "the one that's usually about", "the one we had out earlier")

# --- Object Substitution ---------------------------------------------------------------------------------------
REPAIR_CUES = ("no", "sorry", "I mean", "wait", "oops", "or rather", "no, no", "sorry, no", "no, wait", "actually")
REPAIR_FILLERS = ("", "", "", "the, ", "um, ", "er, ", "oh, ")
SLIP_REMARKS = (
    "Silly me.",
    "I keep doing that.",
    "My words come out muddled.",
    "{Spouse_name} used to laugh at me for that.",
    "Goodness, my head today.",
    "They all seem alike to me now.",
    "I always mix those up.",
    "I'm in a muddle today.",
    "Dear oh dear.",
    "Where's my mind gone.",
    "I said it wrong again.",
    "My tongue runs ahead of me.",
)
CORRECTION_LEADS = (
    "", "", "Oh, ", "Sorry, ", "No, ", "Wait, ", "Oops, ", "Hmm, no, ", "Oh dear, ", "Actually, ", "Goodness, ",
    "Dear me, ", "Oh, sorry, ", "No, wait, ",
)  # fmt: skip
CORRECTION_CORES = (
    "I meant {name}",
    "not {comp}, {name}",
    "{name}, not {comp}",
    "{name}, I should have said",
    "it's {name}, not {comp}",
    "I mean {name}",
    "{name} {name_is} what I want",
    "I said {comp}, didn't I, I meant {name}",
    "not {comp} at all, {name}",
    "{name}, sorry",
    "I've said {comp} again, it's {name}",
    "{comp} {comp_was} wrong, {name}",
    "{name} I mean, {name}",
    "{name}, that's the one",
)
CORRECTION_TAGS = ("", "", "", ", sorry", ", of course", ", silly me", ", dear", ", yes", ", that's it")
# Level 3: a second slip inside the request, then corrections that take both back.
SECOND_SLIPS = ("{comp2}, no", "{comp2}, wait", "I mean {comp2}, no", "or {comp2}, no", "{comp2}, sorry, no")
FINAL_CORES = (
    "not {comp}, not {comp2} either, {name}",
    "not {comp}, sorry, {name}, I meant {name}",
    "not {comp}, not {comp2}, {name}, yes, {name}",
    "I mean {name}, not {comp}, sorry, {name}",
    "not {comp}, wait, {name}, I mean {name}",
    "not {comp2}, I meant {name}, {name}",
    "{name}, not {comp}, {name}, sorry",
    "not {comp}, or rather, not {comp2}, {name}",
    "{name}, sorry, not {comp}, {name} I mean",
    "not {comp}, wait, {name}, yes, {name}",
    "I keep saying {comp}, I mean {name}, {name}",
    "not {comp2}, no, and not {comp}, it's {name}",
)
FINAL_LEADS = (
    "", "Sorry, ", "No, no, ", "Hmm, no, ", "Wait, that's not right, ", "Scratch that, ", "Oops, ", "Goodness, ",
    "Oh dear, ", "Dear me, ", "My mistake, ", "That's wrong, ", "Oh, sorry, ", "No, ",
)  # fmt: skip

# --- Empty Speech -----------------------------------------------------------------------------------------------
# Each is an expression the verifier's empty-speech list knows; one cluster holds one or two.
FILLERS = (
    "you know",
    "well",
    "sort of",
    "kind of",
    "and all that",
    "like",
    "it is what it is",
    "and what have you",
    "or whatever",
    "this and that",
    "I don't know",
    "how do you say",
    "and everything",
    "if you follow me",
    "um",
    "uh",
    "and so on",
    "as they say",
    "anyhow",
    "hmm",
    "here and there",
)
# Discourse markers: most inside clusters are one of these (the paper's empty speech is mostly such markers).
MARKERS = ("you know", "well", "you see", "like", "sort of", "kind of", "um", "uh", "hmm", "anyhow")
# Discourse words that may join a filler in one cluster (never more than three words of filler in a row).
FILLER_PARTNERS = ("I mean", "oh", "so", "right", "er", "okay", "mind you", "anyway", "now", "you see")
EMPTY_LEADS = (
    "Well", "Oh", "So", "Anyway", "Um", "Hmm", "Uh", "Right", "Oh well", "Well now", "So anyway", "Okay", "Ah well",
    "Still", "Mind you", "Anyhow",
)  # fmt: skip
EMPTY_CORES = (
    "that's life",
    "such is life",
    "the way of the world",
    "one of those days",
    "all the same in the end",
    "it is what it is",
    "that's how it goes",
    "what can you do",
    "there we are",
    "no use fussing",
    "same old story",
    "the usual business",
    "the long and short of it",
    "this and that",
    "one way or another",
    "these things happen",
    "such a business",
    "round and round it goes",
    "here and there",
    "the way it is",
    "and so on and so forth",
    "one thing and another",
    "there you go",
    "all sorts",
    "it's all the same",
    "you know how it is",
    "I don't know, really",
)
# Empty cores without a pronoun, for Level 3 (whose noun rate and pronoun share the paper keeps near Level 2's).
EMPTY_CORES_PLAIN = (
    "the way of the world",
    "one of those days",
    "all the same in the end",
    "no use fussing",
    "same old story",
    "the usual business",
    "the long and short of it",
    "one way or another",
    "such a business",
    "round and round",
    "here and there",
    "and so on and so forth",
    "one thing and another",
    "all sorts",
    "such is life",
    "the way of things",
    "the same old business",
)
EMPTY_TAGS = ("", "", "", ", you know", ", I suppose", ", really", ", kind of", ", sort of", ", and all that", ", eh")
EMPTY_TAIL_CUES = (
    "you know", "sort of", "kind of", "and all that", "I don't know", "and what have you", "or whatever",
    "and everything", "and so on",
)  # fmt: skip

# --- Topic Drift --------------------------------------------------------------------------------------------------
# Near the task: a remark on a scene object, sometimes tied to a task object ({t_...}).
NEAR_TIED = frames(
    (DURABLE, "{T_the} always lived next to {x_the} when {spouse_name} was alive.", DURABLE, True),
    (PORTABLE, "{Spouse_name} always kept {t_the} right by {x_the}, I never knew why.", PORTABLE),
    (GIFTS, "{X_the} and {t_the} came from the same shop in {hometown}, I think.", GIFTS),
    (GIFTS, "{X_the} {x_was} a wedding present, same as {t_the}.", GIFTS),
    ("*", "{T_the} and {x_the}, that's the two {grandchild_name} always notices.", "*"),
    (HOUSEHOLD, "{X_the} {x_has} been in this house as long as {t_the}.", HOUSEHOLD),
    (FURNITURE, "Funny, {x_the} {x_is} right where {t_the} used to be.", FURNITURE),
    ("produce", "{T_the} and {x_the}, my mother grew both in the garden in {hometown}.", "produce"),
    ("food", "We had {x_a} and {t_a} every Sunday when {child_name} was little.", "food"),
    ("crockery cutlery cookware", "{X_the} goes with {t_the}, it was all one service from {sibling_name}.", "crockery"),
    ("*", "{Grandchild_name} drew {t_the} and {x_the} for me once, at school.", "*"),
    ("*", "{T_the} and {x_the}, I could find those two in the dark.", "*"),
    (HOUSEHOLD, "We had {t_a} and {x_a} on {street} too, in the very same spots.", HOUSEHOLD),
    (DURABLE, "I always think of {spouse_name} when I notice {t_the} next to {x_the}.", DURABLE),
    (FURNITURE, "{T_the} used to be over by {x_the}, before {child2_name} rearranged everything.", FURNITURE),
    (PORTABLE, "My mother always kept {t_a} and {x_a} side by side, back in {hometown}.", PORTABLE),
    (FURNITURE, "{Pet} used to sleep between {t_the} and {x_the}.", FURNITURE),
    ("*", "{Friend_name} always comments on {t_the} and {x_the}.", "*"),
    (DURABLE, "Funny how {t_the} and {x_the} have both lasted longer than the house on {street}.", DURABLE),
)
NEAR = frames(
    (HOUSEHOLD, "{X_that} {x_has} been here for ages."),
    ("*", "{Spouse_name} never liked {x_the}."),
    ("*", "Funny, I was thinking about {x_the} this morning."),
    (HOUSEHOLD, "We've had {x_that} since we moved to {street}."),
    ("*", "{Grandchild_name} always asks about {x_the}."),
    (GIFTS, "{Sibling_name} gave us {x_the}, you know."),
    (DURABLE + " fixture", "{X_the} {x_was} in the same spot when {child_name} was small."),
    (GIFTS + " storage", "My mother had {x_one} just like {x_that}."),
    ("*", "I notice {x_the} every time I come in here."),
    (HOUSEHOLD, "{X_the} {x_is} older than {child_name}, I think."),
    (DURABLE, "{Friend_name} has {x_one} exactly the same."),
    ("appliance lamp gadget", "{X_the} made a funny noise last week."),
    ("keepsake picture plant textile", "{X_the} always makes me think of {hometown}."),
    ("crockery cookware cutlery", "{X_the} came from our first house on {street}."),
    ("pocket gadget reading", "I lost {x_the} for a whole week once."),
    ("seat table storage", "{X_the} came with us from {street}."),
    ("food", "{Spouse_name} never tired of {x_the}.", "", False),
    ("food", "{Spouse_name} never tired of {x_the}, bless {spouse_him}.", "", True),
    ("plant", "{X_the} was a present from {friend_name}."),
    ("sport", "{X_the} belonged to {child_name} once."),
    ("bottle", "{X_the} reminds me of the parties we had on {street}."),
    ("toiletry textile", "{X_the} {x_is} the sort my mother always bought."),
)
# A memory of the speaker's own, with a scene object.
MEMORY = frames(
    (GIFTS, "My mother had {x_one} just like {x_that} in her front room."),
    (GIFTS, "{Sibling} gave us {x_one} like {x_that} for our wedding."),
    (DURABLE, "{Spouse_name} used to say {x_the} {x_was} the best thing we ever bought.", "", False),
    (GIFTS + " storage seat table", "We had {x_one} like {x_that} at {holiday}, years ago."),
    ("keepsake crockery cookware picture", "{Spouse_name} bought {x_a} at the market in {hometown} once."),
    (DURABLE, "There {x_was} {x_one} just like {x_that} at {workplace} when I was {job}."),
    ("crockery cookware food cutlery", "{Colleague} at {workplace} always had {x_a} on the go."),
    ("keepsake textile sport", "{Grandchild_name} used to hide {x_the} when {grandchild_he} was tiny."),
    ("sport", "{Child_name} broke a pane with {x_a} once, playing in the yard."),
    ("produce", "We grew our own on the allotment in {hometown}, you know, {x_name} and all."),
    ("food", "My mother sent me to the shop for {x_a} every Saturday."),
    ("food", "At {holiday} we had {x_a} with every meal, near enough."),
    ("seat", "{Spouse_name} fell asleep in {x_one} like {x_that} every evening.", "", False),
    ("seat", "{Spouse_name} used to fall asleep in {x_that} every evening.", "", True),
    ("table storage", "{Spouse_name} made {x_one} just like {x_that} in the shed, you know."),
    ("picture keepsake", "{X_the} reminds me of the one in my aunt's hall in {hometown}."),
    ("lamp appliance", "We saved for months for {x_one} like {x_that} when we married."),
    ("gadget", "{Child_name} showed me how {x_the} works three times, bless {child_him}."),
    ("pocket", "I left {x_a} on the bus once, and {spouse_name} went all the way to the depot."),
    ("reading", "{Friend_name} and I used to swap {x_the} over the fence."),
    ("textile", "My mother made {x_one} like {x_that} herself, on her old machine."),
    ("textile", "At {holiday} the landlady kept a close eye on {x_the}, and on us."),
    ("cleaning", "{Spouse_name} bought {x_a} from a man at the door once, and we never used {x_it}."),
    ("plant", "{Spouse_name} talked to {x_the} every morning, I'm sure of it.", "", False),
    ("plant", "My father won a prize in {hometown} for {x_one} like {x_that}."),
    ("bottle", "My mother kept {x_one} just like {x_that} by her back door."),
    ("keepsake", "{X_the} came all the way from {holiday} on my lap."),
    ("crockery", "{Child2_name} broke {x_one} just like {x_that} on {child2_his} fifth birthday."),
    ("cookware cutlery", "{X_the} {x_was} my mother's, and her mother's before that."),
    ("storage", "We kept our ration coupons in {x_one} like {x_that}."),
    ("appliance", "Our first {x_name} came from the shop on {street}, and it lasted twenty years."),
    (FURNITURE + " fixture textile", "{Pet} used to sleep right next to {x_the}."),
    (DURABLE, "{Friend_name} always said {x_the} {x_was} too good for us."),
    ("gadget pocket", "{Colleague} at {workplace} had {x_a} before anyone else."),
    ("seat table", "We bought {x_one} like {x_that} with the money from {workplace}."),
    ("lamp picture", "{X_the} {x_was} in the front room on {street} for years."),
    ("keepsake crockery textile", "{Sibling_name} always wanted {x_the}, and never got {x_it}."),
)
# Far from the task: the speaker's life (no object).
FAR = (
    "I was {job} at {workplace} for years, you know.",
    "{Job_detail}",
    "{Colleague} from {workplace} still sends a letter at Christmas.",
    "We used to go to {holiday} every August.",
    "{Spouse_name} and I met at a dance in {hometown}.",
    "{Child_name} rang on Sunday, or was it Saturday.",
    "{Grandchild_name} is so tall now, taller than {child_name}.",
    "{Pet} used to wait at the gate for {spouse_name}.",
    "I never missed {habit} in those days.",
    "The summers were longer in {hometown}, I'm sure of it.",
    "My sister and I walked to school in {hometown}, rain or shine.",
    "We lived on {street} for thirty years.",
    "{Friend_name} has moved away now, I think.",
    "{Sibling_name} and I still talk every week.",
    "There was a dance hall in {hometown} where everybody went on Saturdays.",
    "{Spouse_name} sang in the choir for forty years.",
    "The buses were every ten minutes when I was at {workplace}.",
    "{Child2_name} was such a quiet baby.",
    "My father kept pigeons behind the house in {hometown}.",
    "We never had much money, but we had a good time.",
    "I miss the old shops on {street}.",
    "{Grandchild_name} wants to be a vet, or a footballer.",
    "We went to {holiday} the year {child2_name} was born.",
    "{Spouse_name} always drove, I never learned.",
    "My mother could sing like a bird.",
    "{Colleague} was the funniest person at {workplace}.",
    "The sea at {holiday} was freezing, but we went in anyway.",
    "Those were the days, at {workplace}.",
    "{Child_name} has {child_his} father's laugh.",
    "I wrote to {sibling_name} every week when {sibling_he} lived abroad.",
    "Christmas on {street} was always a squash, all of us together.",
    "{Pet} lived to be sixteen, you know.",
    "I still think about {hometown} a lot.",
    "{Friend_name} taught me to knit, years ago.",
    "It was all fields round here once.",
)
FAR_LATE = (
    "{Spouse_name} has been gone eight years now.",
    "I still talk to {spouse_name}, you know, in my head.",
    "{Spouse_name} would have been ninety this year.",
)
FAR_ALIVE = (
    "{Spouse_name} is out at the club again, I expect.",
    "{Spouse_name} and I have been married over fifty years.",
    "{Spouse_name} still does {spouse_his} crossword every morning.",
)
# A short second remark at Level 1, after the object remark (no object, no request).
ASIDES = (
    "Funny, that.",
    "Anyway.",
    "It's all a long time ago.",
    "Such a long time ago.",
    "Never mind.",
    "Still.",
    "Time flies.",
    "Those were the days.",
    "Goodness.",
    "Funny how you remember.",
    "Oh well.",
    "Ah, well.",
)
# The short second remark at Level 1 when the task names an object: it comes back to that object.
ASIDES_TIED = (
    "Funny, {t_the} of all things.",
    "{T_the}, of all things.",
    "All that from {t_the}.",
    "Funny what {t_the} makes me think of.",
    "{T_the} and {t_its} stories.",
    "Goodness, {t_the}.",
    "Funny how {t_the} does that.",
    "Years, {t_the} {t_has} been about.",
)
DRIFT_LEADS = ("Oh, ", "You know, ", "Mind you, ", "Anyway, ", "Honestly, ", "Goodness, ", "Still, ", "Ah, ", "Well, ")

# --- Intrusion -----------------------------------------------------------------------------------------------------
THOUGHTS = (
    "is that the doorbell?",
    "what day is it today?",
    "did somebody ring?",
    "was that thunder?",
    "has the postman been?",
    "those birds are noisy today.",
    "is {grandchild_name} coming today?",
    "where are my glasses?",
    "is somebody at the door?",
    "did I feed {pet}?",
    "is it lunchtime yet?",
    "was that {child_name} on the telephone earlier?",
    "did {spouse_name} go out?",
    "is it Tuesday?",
    "did I ring {sibling_name} back?",
    "what time is {child_name} coming?",
    "is it raining again?",
    "did the milkman come?",
    "is that {friend_name} in the garden?",
    "is the gate shut?",
    "what's that noise upstairs?",
    "have I had my tablets?",
    "is it the rubbish day today?",
)
FOLLOWS = (
    "I can never remember these days.",
    "Oh, it doesn't matter.",
    "{Child_name} would know.",
    "I'll ask {friend_name} later.",
    "Never mind, never mind.",
    "It's always something.",
    "The days all run together now.",
    "{Sibling_name} said {sibling_he}'d ring today.",
    "{Child_name} usually sorts all that out.",
    "It was the same last week.",
    "Nobody tells me anything.",
    "I thought I heard a knock.",
    "Perhaps it was next door.",
    "My memory is hopeless today.",
    "I keep losing track of the days.",
    "{Colleague} used to say I'd forget my own head.",
    "It'll come back to me.",
    "Probably nothing at all.",
    "Always the way, isn't it.",
    "The nurse comes on Wednesdays.",
    "Such a commotion outside.",
    "{Spouse_name} would have known.",
    "We had a storm like that once, in {hometown}.",
    "Somebody was here earlier.",
    "I had a letter about it somewhere.",
    "{Grandchild_name} said {grandchild_he} might pop in.",
    "{Pet} always knew when somebody was coming.",
    "It's been like that all week.",
    "I do muddle the days.",
    "{Friend_name} mentioned it yesterday.",
    "It was never like this on {street}.",
    "{Child2_name} is coming on Sunday, I think.",
)
FRAGMENTS = (
    "The birds, so loud.",
    "The post, did it come?",
    "Letters, bills, nothing.",
    "Sunday, or Monday?",
    "Tuesday, is it?",
    "My glasses, somewhere.",
    "{Pet}, fed? Fed, surely.",
    "Rain again, always rain.",
    "{Sibling_name}, {sibling_he} rang, or not.",
    "{Grandchild_name}, {grandchild_his} birthday, soon.",
    "The doorbell, no, nobody.",
    "Lunch, soon, surely.",
    "The bus, half past, or quarter to.",
    "{Child_name}, calling later.",
    "The neighbours, so noisy.",
    "Church bells, Sunday then.",
    "My coat, the blue one.",
    "Appointment, Thursday, or Friday.",
    "The milkman, paid him? Yes.",
    "The boiler, making that noise.",
    "Pension day, Thursday.",
    "{Friend_name}, poorly again.",
    "{Spouse_name}, out, or upstairs.",
    "{Hometown}, years ago.",
    "{Street}, the old house.",
    "Supper, what for supper.",
    "Tablets, taken? Taken.",
    "The radio, left on?",
    "The gate, still open.",
    "Frost tonight, they said.",
    "{Colleague}, from {workplace}.",
    "Footsteps, upstairs?",
    "{Child2_name}, Sunday, or next week.",
    "The hairdresser, Friday.",
)
RESUMPTIONS = (
    "Anyway, ",
    "Where was I, oh yes, ",
    "Now then, ",
    "As I was saying, ",
    "Oh yes, ",
    "Back to it, ",
    "Ah yes, ",
    "Right, ",
    "Sorry, yes, ",
    "Now, ",
    "So, as I was saying, ",
    "Never mind, ",
    "Where was I, ",
    "Anyhow, ",
)
RESTATEMENTS = (
    "Yes, {restate}",
    "Now where was I, {restate}",
    "So, {restate}",
    "Oh yes, {restate}",
    "Where was I, oh, {restate}",
    "Right, yes, {restate}",
    "As I said, {restate}",
    "Back to it, {restate}",
    "I was saying, {restate}",
    "Yes, that's right, {restate}",
)
# Naming the target once in the clean control when the seed does not (see rules_v3.conversationalize).
UNNAMED_TARGET = ("It's the {name} I'm after.", "The {name} is what I'm after.", "I'm after the {name}.")
UNNAMED_TARGET_ON = ("It's the {name} on the {container} I'm after.", "The {name} goes on the {container}.")
# Closings moved out of the request sentence when a correction follows it.
CLOSING_SENTENCES = {"thanks": "Thanks.", "thank you": "Thank you."}
