"""Phrase banks of the rules generator (version `rules-v1`).

Inserted wording never names an object (objects come from the task's scene list, through the lexicon),
never uses a state word (hot, cold, clean, ...) and never uses a dash or a colon; intrusions also avoid the
task verbs. The verifier enforces the first three.
"""

from __future__ import annotations

PHRASES_VERSION = "rules-v1"

# --- clean control --------------------------------------------------------------------------------------------
GREETINGS = (
    "Hi",
    "Hello",
    "Hey",
    "Hi there",
    "Hello there",
    "Hey there",
    "Good morning",
    "Morning",
    "Good afternoon",
    "Good evening",
    "Hello again",
    "Oh, hello",
    "Hiya",
    "Hi, it's me",
    "Hello, robot",
    "Hey, robot",
)
GREETING_ENDS = (", ", "! ", ". ")
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
STATEMENT_FRAMES = (
    "I'd like you to {body}.",
    "I need you to {body}.",
    "it would be great if you could {body}.",
    "I want you to {body}, please.",
    "when you have a moment, {body}.",
    "if you could {body}, that would help me.",
    "please {body}.",
    "{body}, please.",
    "{body} for me, would you?",
    "I was hoping you could {body}.",
    "go ahead and {body}, please.",
    "{body} when you get a chance.",
)
CLOSINGS = (
    "",
    "",
    "",
    "Thanks.",
    "Thank you.",
    "Thanks a lot.",
    "Thank you so much.",
    "I'd appreciate it.",
    "That would be lovely.",
    "Thanks, dear.",
    "Much appreciated.",
)

# --- Referential Imprecision -------------------------------------------------------------------------------
VAGUE_NOUNS = ("thing", "thingy", "whatsit", "whatchamacallit", "thingamajig", "doodad", "thingamabob")
IMMEDIATE_CLARIFIERS = (
    "{vague}, I mean {name}",
    "{vague}, it's {name}",
    "{vague}, I think it's {name}",
    "{vague}, what is it, {name}",
    "{vague}, oh, it's {name}",
    "{vague}, you know, {name}",
    "{vague}, that is, {name}",
    "{vague}, I mean it's {name}",
)
DELAYED_CLARIFICATIONS = (
    "{Name}, I mean.",
    "I mean {name}.",
    "It's {name}. That's the one.",
    "{Name}, that's what I'm after.",
    "Oh, it's {name}, I should say.",
    "{Name}. That's what I meant.",
    "I'm talking about {name}, you see.",
    "It's {name} I mean.",
)
WORD_SEARCH = (
    "Oh, what is it. I know it, I do.",
    "What do you call it. It's, it's.",
    "Oh, I know what it is. It's that one.",
    "What's it called. You know it, I'm sure.",
    "Now what is it. It'll come to me.",
    "I can't think what it's called. It's, oh.",
)
FINAL_NAMING = (
    "{Name}. Yes, it's {name}.",
    "{Name}! That's it.",
    "It's {name}, I think. Yes, that's it.",
    "{Name}, that's it, that's the one.",
    "Ah, {name}. Yes, that's what it is.",
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
IMMEDIATE_REPAIRS = (
    "no, no, {name}, {name}",
    "no, sorry, the, {name}",
    "I mean {name}, {name}",
    "no, no, {name}",
    "oops, no, {name}",
    "no, the, the, {name}",
    "or rather {name}, yes, {name}",
)
DELAYED_REPAIRS = (
    "Oh, not {comp}. {Name}, I meant {name}.",
    "Wait, no. Not {comp}, {name}.",
    "Sorry, I mean {name}, not {comp}.",
    "No, that's wrong. {Name}, not {comp}.",
    "Actually, I meant {name}. Not {comp}.",
)
SECOND_SUBSTITUTIONS = ("{comp2}, no", "{comp2}, wait", "I mean {comp2}, no")
FINAL_REPAIRS = (
    "Hmm, no. Not {comp}, and not {comp2} either. {Name}. It's {name} I want.",
    "No, wait, that's not right. Not {comp}. Sorry. {Name}, I meant {name}.",
    "Oh, scratch that. Not {comp}, not {comp2}. {Name}. Yes, {name}.",
    "Sorry, no. I keep saying {comp}. I mean {name}. {Name}.",
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
EMPTY_SENTENCES = (
    "Well, you know how it is.",
    "It's all the same, really, isn't it.",
    "That's how it goes, I suppose.",
    "Oh, you know, this and that.",
    "There we are, then.",
    "It's just one of those days, you know.",
    "Well, what can you do.",
    "I don't know, it's the way it is.",
    "Oh dear, and so on and so forth.",
    "You know, one way or another.",
)

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
DRIFT_LEADS = ("", "", "Oh, ", "You know, ", "Mind you, ", "Anyway, ")

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
)
INTRUSION_FRAGMENTS = (
    "Oh. The birds. So loud.",
    "The post. Did it come? No.",
    "Sunday. Or Monday. Hm.",
    "My glasses. Somewhere.",
    "The cat. Fed? Yes. Fed.",
    "Rain again. Always rain.",
    "Margaret. She rang. Or not.",
    "The doorbell. No. Nobody.",
)
RESUMPTIONS = (
    "Anyway, ",
    "Where was I? Oh yes, ",
    "Right, ",
    "Sorry, yes, ",
    "Now, ",
    "So, as I was saying, ",
    "Never mind, ",
)
RESTATEMENTS = (
    "Yes. {restate}",
    "Now where was I. {restate}",
    "So. {restate}",
    "Oh yes. {restate}",
    "Where was I. Oh. {restate}",
)
