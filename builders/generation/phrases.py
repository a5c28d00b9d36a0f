"""Phrase banks of the rules generator (version `rules-v2`, calibrated against the paper's marker table).

Inserted wording never names an object (objects come from the task's scene list, through the lexicon),
never uses a state word (hot, cold, clean, ...) and never uses a dash or a colon; intrusions also avoid the
task verbs. The verifier enforces the first three.
"""

from __future__ import annotations

PHRASES_VERSION = "rules-v2"

# --- clean control --------------------------------------------------------------------------------------------
GREETINGS = (
    "Hi",
    "Hello",
    "Hey",
    "Hi there",
    "Hello there",
    "Hey there",
    "Good morning",
    "Good afternoon",
    "Good evening",
    "Hello again",
    "Hiya",
    "Hi again",
    "Hello, dear",
)
# The greeting opens the request sentence ("Hi, could you ..."): the paper's clean controls are one sentence
# (sentence-level relevance 0.957), so a greeting of its own ("Hi!") would halve their relevance; a vocative
# ("Hello, robot") lowers the request's cosine to the seed most (0.70 to 0.77 against 0.85), so none is used.
GREETING_ENDS = (", ",)
# Frames around the request body; {body} is the seed wording, lowercased at the start.
QUESTION_FRAMES = (
    "could you {body}?",
    "can you {body} for me?",
    "would you {body}, please?",
    "do you think you could {body}?",
    "will you {body}?",
    "could you please {body}?",
    "would you be able to {body}?",
    "can you please {body}?",
)
# Statements and imperatives; half name no person, as the paper's clean controls have few pronouns (0.209 of
# nouns and pronouns).
STATEMENT_FRAMES = (
    "I'd like you to {body}.",
    "it would be great if you could {body}.",
    "when you have a moment, {body}.",
    "please {body}.",
    "{body}, please.",
    "{body} for me, would you?",
    "go ahead and {body}, please.",
    "{body} when you get a chance.",
    "please {body} now.",
    "{body}, thanks.",
    "{body}, thank you.",
    "please {body} today.",
    "kindly {body}.",
    "time to {body}, please.",
    "please {body}, thank you.",
    "{body}, if possible.",
    "please {body} at some point.",
)
# Closings stay inside the request sentence (", thanks.") in the frames above; none stands alone.
CLOSINGS = ("",)

# --- Referential Imprecision -------------------------------------------------------------------------------
VAGUE_NOUNS = ("thing", "thingy", "whatsit", "whatchamacallit", "thingamajig", "doodad", "thingamabob")
# A third name the speaker or listener (I mean, you know, you see, it's): the paper's Level 1 pronoun share (0.188)
# dips below its clean one (0.209); ours stays just above clean, keeping the paper's arrow (see markers/paper.py).
IMMEDIATE_CLARIFIERS = (
    "{vague}, I mean {name}",
    "{vague}, {name} really",
    "{vague}, {name}",
    "{vague}, oh, {name}",
    "{vague}, you know, {name}",
    "{vague}, um, {name}",
    "{vague}, the, {name}",
    "{vague}, or rather {name}",
    "{vague}, it's {name}",
    "{vague}, you see, {name}",
    "{vague}, well, {name}",
    "{vague}, er, {name}",
)
DELAYED_CLARIFICATIONS = (
    "{Name}, I mean.",
    "I mean {name}.",
    "It's {name}, that's the one.",
    "{Name}, that's what I'm after.",
    "Oh, it's {name}, I should say.",
    "{Name}, that's what I meant.",
    "I'm talking about {name}, you see.",
    "It's {name} I mean.",
    "The name is {name}, of course.",
    "{Name}, that's the word.",
    "I meant {name} all along.",
    "{Name}, if I'd said it properly.",
)
# Word-finding trouble, composed from a lead and a search (few pronouns, as in the paper's Level 3: 0.351).
WORD_SEARCH_LEADS = ("Oh", "Now", "Hmm", "Well", "Ah", "Um", "Uh", "Er")
WORD_SEARCH = (
    "what is it",
    "what's it called",
    "I know it",
    "it's gone",
    "I had it",
    "where has it gone",
    "it won't come",
    "what do I call it",
    "it's right there",
    "I can see it",
    "I've lost it",
    "it's slipped away",
    "how do I say it",
    "I know this",
    "what was it",
    "it's coming",
)
# A second search sentence at Level 3, with the pronouns of a speaker searching (the paper: 0.351 at Level 3).
WORD_SEARCH_SELF = (
    "I know it, I do.",
    "It'll come to me.",
    "What do you call it.",
    "I can't think of it.",
    "You know the one I mean.",
    "I had it a minute ago.",
    "What is it now.",
    "I use it every day.",
    "You'll know it when you see it.",
    "It's gone right out of my head.",
    "I had the word a second ago.",
    "You know what I mean.",
    "It's on the tip of my tongue.",
    "I'll think of it in a minute.",
    "What do they call it.",
    "You've seen me with it.",
    "I should know this.",
    "It starts with, oh, I don't know.",
    "I say it every day.",
    "It's silly, I know it.",
    "Help me, what's it called.",
    "I'm hopeless with names now.",
    "You know it, I'm sure.",
    "I had it on my list.",
)
FINAL_NAMING = (
    "{Name}. Yes, {name}.",
    "{Name}, that's it.",
    "{Name}, of course.",
    "{Name}, the very one.",
    "Aha, {name}. Yes.",
    "{Name}, that's the one.",
    "Yes, {name}. {Name}.",
    "{Name}, finally.",
    "Of course, {name}.",
    "There, {name}.",
)
SECOND_VAGUE = ("that one", "the one there", "this one", "that thing")

# Circumlocutions for object types: what the thing is for or what it looks like, without its name.
CIRCUMLOCUTIONS: dict[str, tuple[str, ...]] = {
    "AlarmClock": ("the one that rings in the morning", "the one that wakes me up"),
    "Apple": ("the round one you bite into", "the one that keeps the doctor away"),
    "BaseballBat": ("the long wooden one you swing", "the wooden one for hitting"),
    "BasketBall": ("the big orange one that bounces", "the orange one you bounce"),
    "Book": ("the one you read, with all the pages", "the one with the story in it"),
    "Bowl": ("the round deep one for cereal", "the one you have your porridge in"),
    "Box": ("the square one you keep things in", "the cardboard one"),
    "Bread": ("the one you make sandwiches with", "the one you toast in the morning"),
    "ButterKnife": ("the blunt little one for spreading", "the one you spread with, not the sharp one"),
    "CD": ("the shiny round one with music on it", "the flat shiny one with the songs"),
    "Candle": ("the waxy one with the wick", "the one with the wick for power cuts"),
    "CellPhone": ("the one you ring people on", "the little one that buzzes when someone calls"),
    "Cloth": ("the floppy square one for wiping", "the one for wiping up spills"),
    "CreditCard": ("the little plastic one for paying", "the plastic one for the shops"),
    "Cup": ("the one you drink from", "the little one for drinks"),
    "DishSponge": ("the squishy one for the dishes", "the squishy yellow one for scrubbing"),
    "Egg": ("the little oval one that cracks", "the one the hens lay"),
    "Fork": ("the one with the prongs you eat with", "the pointy one with the tines"),
    "HandTowel": ("the soft one for drying your hands", "the fluffy one you dry with"),
    "Kettle": ("the one that whistles when the water boils", "the one for boiling water for tea"),
    "KeyChain": ("the jangly ones for the front door", "the ones you lock the door with"),
    "Knife": ("the sharp one for cutting", "the one with the blade"),
    "Ladle": ("the big deep one for serving soup", "the one with the long handle for soup"),
    "Laptop": ("the one you type on that folds open", "the folding one with the screen and the keyboard"),
    "Lettuce": ("the leafy green one for salad", "the green leafy one, crunchy"),
    "Mug": ("the one I have my coffee in, with the handle", "the big one with the handle for drinks"),
    "Newspaper": ("the one with the news and the crossword", "the one with the headlines"),
    "Pan": ("the flat one with the long handle for frying", "the one you fry with"),
    "Pen": ("the one you write with, the inky one", "the one you sign your name with"),
    "Pencil": ("the one you write with that needs sharpening", "the wooden one you draw with"),
    "Pillow": ("the soft one for your head", "the soft one you lean on"),
    "Plate": ("the flat round one you eat off", "the one for dinner, flat and round"),
    "Pot": ("the big deep one for boiling", "the heavy one with two handles for soup"),
    "Potato": ("the lumpy brown one that you mash", "the one you make chips from"),
    "RemoteControl": ("the one with the buttons for the channels", "the clicker for the channels"),
    "SaltShaker": ("the little one you shake over your chips", "the shaker for the chips"),
    "SoapBar": ("the slippery one that makes bubbles", "the slippery one for your hands"),
    "SoapBottle": ("the one you pump for your hands", "the squeezy one you pump"),
    "Spatula": ("the flat one for flipping", "the flat one you flip pancakes with"),
    "Spoon": ("the one you stir your tea with", "the one for soup"),
    "SprayBottle": ("the squirty one with the trigger", "the one you squirt with, with the trigger"),
    "Statue": ("the little carved ornament", "the ornament, the little figure"),
    "TennisRacket": ("the one with the strings you hit with", "the stringy one for the courts"),
    "TissueBox": ("the one for blowing your nose", "the one you pull from when your nose runs"),
    "ToiletPaper": ("the soft white one you need in the bathroom", "the soft white one for the bathroom"),
    "Tomato": ("the red squishy one for salads", "the round red one for sauce"),
    "Vase": ("the one you put flowers in", "the tall one for flowers"),
    "Watch": ("the one you wear on your wrist that tells the time", "the one on the wrist, with the hands"),
    "WateringCan": ("the one with the spout for the garden", "the one for the flowers, with the spout"),
    "WineBottle": ("the green glass one for dinner parties", "the one with the cork"),
}
GENERIC_CIRCUMLOCUTIONS = ("the one I always use", "the one that's usually around here", "the one we had out earlier")

# --- Object Substitution -----------------------------------------------------------------------------------
# One self-correction cue each, a few with two: the paper's Level 1 repair rate is about 6 per 100 words.
IMMEDIATE_REPAIRS = (
    "no, {name}, {name}",
    "sorry, {name}",
    "I mean {name}, {name}",
    "oops, the, the, {name}",
    "or rather {name}, {name}",
    "wait, the, {name}",
    "no, the, the, {name}",
    "sorry, the, {name}",
    "I mean, {name}, {name}",
    "or rather, the, {name}",
    "sorry, {name}, {name}",
    "oops, the, {name}",
)
# One sentence after the request; the name comes twice (repetition lowers MTLD, as in the paper's Level 2).
# Four in ten hold two cues, so Level 2 repairs a little more than Level 1 (the paper's 4.32 is below its
# Level 1, which the level definitions do not call for: we keep the order clean < L1 < L2 < L3).
DELAYED_REPAIRS = (
    "{Name}, I meant {name}.",
    "Wait, no, {name}, {name}.",
    "Sorry, no, {name}, {name} that is.",
    "Oh, I meant {name}. {Name}.",
    "Oops, sorry, {name}, {name}.",
    "I mean {name}, {name}.",
    "Hmm, no, {name}, sorry. {Name}.",
    "Oh, not {comp}, it's {name}.",
    "Sorry, I should say {name}. {Name}.",
    "Or rather {name}. {Name}.",
)
SECOND_SUBSTITUTIONS = ("{comp2}, no", "{comp2}, wait", "I mean {comp2}, no")
# Level 3 settles the target after two or more corrections; the first one also serves a single competitor.
FINAL_REPAIRS = (
    "Sorry, I keep saying {comp}, I mean {name}, {name}.",
    "Hmm, no, not {comp}, and not {comp2} either, {name}, it's {name}, {name} I want.",
    "Wait, that's not right, not {comp}, sorry, {name}, I meant {name}.",
    "Scratch that, not {comp}, not {comp2}, {name}, yes, {name}, {name}.",
    "No, no, not {comp}, not {comp2}, {name}, {name}.",
    "Oops, I mean {name}, not {comp}, sorry, {name}.",
    "Goodness, not {comp}, wait, {name}, I mean {name}, {name}.",
    "That's wrong, sorry, not {comp2}, I meant {name}, {name}.",
    "Oh dear, no, {name}, not {comp}, {name}, {name}.",
    "Dear me, not {comp}, or rather, not {comp2}, {name}, {name}.",
    "Sorry, sorry, {name}, not {comp}, {name} I mean.",
    "My mistake, not {comp}, wait, {name}, yes, {name}.",
)
# Kinds of things people confuse with one another: competitors come from the same kind first.
OBJECT_KINDS: tuple[frozenset[str], ...] = (
    frozenset({"Apple", "Tomato", "Potato", "Egg", "Bread", "Lettuce"}),
    frozenset({"Fork", "Spoon", "Knife", "ButterKnife", "Ladle", "Spatula"}),
    frozenset({"Mug", "Cup", "Bowl", "Plate", "Pot", "Pan", "Kettle"}),
    frozenset({"SoapBar", "SoapBottle", "Cloth", "HandTowel", "ToiletPaper", "DishSponge", "SprayBottle", "TissueBox"}),
    frozenset({"KeyChain", "CreditCard", "CellPhone", "RemoteControl", "Watch", "Pen", "Pencil", "CD"}),
    frozenset({"Book", "Newspaper", "Laptop", "AlarmClock", "CD"}),
    frozenset({"Vase", "Statue", "Candle", "WateringCan", "Box", "Pillow", "TeddyBear", "HousePlant"}),
    frozenset({"BaseballBat", "BasketBall", "TennisRacket"}),
    frozenset({"WineBottle", "Glassbottle", "SprayBottle", "SaltShaker", "PepperShaker", "SoapBottle"}),
)

# --- Empty Speech ------------------------------------------------------------------------------------------------
# Inside the request: one or two discourse markers, or a stock phrase. Every cluster holds an expression the
# verifier's empty-speech list knows; about half name a person ("you know"), as the paper's pronoun share rises.
DISCOURSE_FILLERS = (
    "you know",
    "well",
    "you see",
    "like",
    "sort of",
    "kind of",
    "um",
    "uh",
    "hmm",
    "anyhow",
)
DISCOURSE_EXTRAS = ("I mean", "oh", "so", "right", "er", "okay", "mind you", "anyway", "now", "you know", "you see")
FILLERS = (
    "you know",
    "well",
    "sort of",
    "kind of",
    "and all that",
    "you see",
    "like",
    "it is what it is",
    "and what have you",
    "or whatever",
    "this and that",
    "I don't know",
    "let me see",
    "how do you say",
    "and everything",
    "if you follow me",
    "um",
    "uh",
    "and so on",
    "as they say",
    "anyhow",
)
# Whole empty sentences: a discourse lead, an empty core, sometimes a tag; composed, so none dominates.
EMPTY_LEADS = ("Well", "Oh", "So", "Anyway", "Um", "Hmm", "Uh", "Right", "Oh well", "Well now", "So anyway", "Okay")
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
    "all sorts of things",
    "these things happen",
    "such a business",
    "round and round it goes",
    "here and there",
    "the way it is",
    "and so on and so forth",
    "one thing and another",
    "that's the way of things",
)
# Tags at the end of a sentence; only some count as empty speech for the verifier there (see rules.py).
EMPTY_TAGS = ("", "", ", you know", ", I suppose", ", really", ", kind of", ", sort of", ", and all that")

# --- Topic Drift -------------------------------------------------------------------------------------------------
# {the} "the lamp", {a} "a lamp", {that} "that lamp"; the first stage stays near the task, later ones drift.
DRIFT_NEAR = (
    "Oh, and {the} could do with a tidy too, now that I notice it.",
    "Is {that} still where I left it?",
    "{That} has been there for ages, hasn't it.",
    "I keep meaning to do something about {the}.",
    "My husband always leaves {the} right there.",
    "Funny, I was just thinking about {the} this morning.",
    "We got {that} the same year we moved in.",
    "Somebody ought to dust {the}, while we're at it.",
)
DRIFT_MEMORY = (
    "My mother had {a} just like that, in her old flat.",
    "It reminds me of {the} my sister gave us for our wedding.",
    "Dad used to mend everything, even {the}, with a bit of string.",
    "The grandchildren used to hide behind {the} at Christmas.",
    "There used to be {a} in the hall of the school where I taught.",
    "We had {a} exactly like it at the seaside house, years ago.",
    "Aunt Edna would never let anyone touch {the} in her front room.",
    "I bought {a} at a jumble sale once, for next to nothing.",
)
DRIFT_FAR = (
    "The bus used to stop right outside our door.",
    "My father whistled the same tune every morning.",
    "We kept chickens for a while, and a goat.",
    "The winters went on forever back then.",
    "I learned to swim in the river behind the mill.",
    "My sister still writes every birthday.",
    "We queued for everything in those days.",
    "The neighbours had a dog called Biscuit.",
    "I worked at the post office for eleven years.",
    "We used to dance to the radio in the kitchen.",
    "Grandad grew the biggest marrows in the village.",
    "The cinema cost sixpence when I was a girl.",
    "Our first car was a little green one.",
    "We walked everywhere, rain or shine.",
    "My mother sang in the church choir.",
    "That was such a long time ago now.",
    "The summers were longer then, I'm sure of it.",
    "We used to go to the coast every August.",
    "Everybody danced at the village hall on Saturdays.",
    "I wonder whatever happened to the Hendersons next door.",
    "My brother had a little red bicycle he never let me ride.",
    "You could hear the church bells for miles on a Sunday.",
    "I still owe Margaret a letter, come to think of it.",
    "The garden was full of roses in those days.",
    "We never had much money, but we were happy.",
)
# Lead-ins for drift sentences; within an utterance none is used twice.
DRIFT_LEADS = ("Oh, ", "You know, ", "Mind you, ", "Anyway, ", "Honestly, ", "Goodness, ", "Still, ", "Ah, ", "Well, ")

# --- Intrusion -----------------------------------------------------------------------------------------------------
INTRUSION_SHORT = (
    "oh, is that the doorbell?",
    "oh, what day is it today?",
    "did somebody ring?",
    "oh, was that thunder?",
    "is it Tuesday already?",
    "has the postman been?",
    "oh, those birds are noisy today.",
    "I think it's going to rain.",
    "now where are my glasses?",
    "is somebody at the door?",
    "oh, did I feed the cat?",
    "is it lunchtime yet?",
)
INTRUSION_FOLLOW = (
    "I can never remember these days.",
    "Oh, it doesn't matter.",
    "My daughter would know.",
    "I'll ask Margaret later.",
    "Never mind, never mind.",
    "It's always something.",
    "The days all run together now.",
    "Margaret said she'd ring today.",
    "I must write it on the calendar.",
    "My son usually sorts all that out.",
    "It was the same last week.",
    "Nobody tells me anything.",
    "I'll have to check later.",
    "The post came late again.",
    "I thought I heard something.",
    "Perhaps it was next door.",
    "My memory is hopeless today.",
    "I keep losing track of the days.",
    "The vicar's coming on Thursday.",
    "It'll come back to me.",
    "Probably nothing at all.",
    "Always the way, isn't it.",
    "The nurse comes on Wednesdays.",
    "Such a commotion outside.",
    "Summer time ended, didn't it.",
    "I was going to ring somebody.",
    "There was something on the radio about it.",
    "My husband would have known.",
    "We had a storm like that once.",
    "Somebody was here earlier.",
    "I ought to write that down.",
    "The girl from the shop said so.",
    "I do get muddled with the days.",
    "It's been like that all week.",
    "My neighbour mentioned it yesterday.",
    "I'm sure I heard a knock.",
    "Everyone's so busy these days.",
    "I had a letter about it somewhere.",
)
# Level 3: short fragmented sentences, a topic and what the mind does with it (one sentence each).
INTRUSION_FRAGMENTS = (
    "The birds, so loud.",
    "The birds again, all morning.",
    "Those birds, every day.",
    "The post, did it come?",
    "The postman, late, always late.",
    "Letters, bills, nothing.",
    "Sunday, or Monday?",
    "Tuesday, is it?",
    "What day, what day.",
    "My glasses, somewhere.",
    "Glasses, where, where.",
    "The cat, fed? Fed, surely.",
    "The cat, out all night.",
    "Rain again, always rain.",
    "Rain, the washing, oh.",
    "Thunder, far off.",
    "Margaret, she rang, or not.",
    "Margaret, her birthday, soon.",
    "The doorbell, no, nobody.",
    "Somebody, at the door?",
    "Lunch, soon, surely.",
    "The bus, half past, or quarter to.",
    "My daughter, calling later.",
    "The neighbours, so noisy.",
    "The dog next door, barking.",
    "Church bells, Sunday then.",
    "My coat, the blue one.",
    "Appointment, Thursday, or Friday.",
    "The milkman, paid him? Yes.",
    "Snow, maybe, later.",
    "The boiler, making that noise.",
    "Pension day, Thursday.",
    "The gardener, due.",
    "Doctor's letter, somewhere.",
    "The vicar, Sunday, or was it.",
    "Rubbish day, tonight, or tomorrow?",
    "That noise, was it the door?",
    "Jimmy, my grandson, so tall now.",
    "Hairdresser, Friday, ten o'clock.",
    "The wind, so strong.",
    "Supper, what for supper.",
    "Tablets, taken? Taken.",
    "The radio, left on?",
    "Mother's brooch, put away.",
    "The gate, still open.",
    "Frost tonight, they said.",
    "Harold, gone now, years.",
    "The library, shut today.",
    "Post office, shut Wednesdays.",
    "Footsteps, upstairs?",
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
)
