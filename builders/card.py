"""The dataset card (`data/README.md`, copied to `dataset_card.md`): YAML configs plus the documentation.

Everything numeric in the card (counts, verification statistics, the markers table) is read from the
build's own outputs, so the card describes the shipped files and nothing else.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from builders.validation.card import validation_section
from talkdem.schema import ALL, CLEAN, MEMORY_BANK, PATTERN_CONFIGS, PATTERNS, TASKS, data_files

__all__ = ["configs_yaml", "markers_table", "render_card", "write_card"]


def configs_yaml() -> str:
    """The card's `configs` block, from the layout `talkdem.schema` declares (clean is the default config)."""
    lines = ["configs:"]
    for config in (*PATTERN_CONFIGS, CLEAN, ALL, MEMORY_BANK, TASKS):
        lines += [f"- config_name: {config}"] + (["  default: true"] if config == CLEAN else []) + ["  data_files:"]
        for split, paths in data_files(config).items():
            if len(paths) == 1:
                lines += [f"  - split: {split}", f"    path: {paths[0]}"]
            else:
                lines += [f"  - split: {split}", "    path:", *(f"    - {path}" for path in paths)]
    return "\n".join(lines)


def _deviation(ours: float, paper: float) -> str:
    if paper == 0:
        return f"{ours - paper:+.2f}"
    return f"{100 * (ours - paper) / abs(paper):+.0f}%"


def markers_table(markers: dict[str, Any]) -> str:
    """Markdown: the paper's marker table next to ours (per-cell deviation, tolerance), then the variety figures."""
    from builders.markers.paper import LEVEL_KEYS, RELATIVE_TOLERANCE

    rows = [
        "| Marker | Pattern | Paper direction | Clean: paper / ours (dev.) | L1: paper / ours (dev.) | "
        "L2: paper / ours (dev.) | L3: paper / ours (dev.) | Moves as in the paper |",
        "| --- | --- | --- | ---: | ---: | ---: | ---: | --- |",
    ]
    inside = total = 0
    for entry in markers["directions"]:
        values, paper = entry["values"], entry.get("paper")
        arrow = "up" if entry["direction"] > 0 else "down"
        digits = 1 if entry["marker"] == "mtld" else 2 if entry["marker"] in {"repair_rate", "discourse_markers"} else 3
        cells = []
        for key in LEVEL_KEYS:
            if paper is None:
                cells.append(f"{values[key]:.{digits}f}")
                continue
            ok = entry["within_tolerance"][key]
            inside, total = inside + ok, total + 1
            mark = "" if ok else " ✗"
            cells.append(
                f"{paper[key]:.{digits}f} / {values[key]:.{digits}f} ({_deviation(values[key], paper[key])}){mark}"
            )
        rows.append(
            f"| {entry['marker_label']} | {entry['pattern_abbreviation']} | {arrow} | "
            + " | ".join(cells)
            + f" | {_moves(entry)} |"
        )
    if total:
        rows += [
            "",
            f"**{inside} of {total} cells** are within max({100 * RELATIVE_TOLERANCE:.0f}% of the paper's value, the "
            "marker's floor) of the paper's (✗ marks the others; floors: 0.5 per 100 words for the two rates, "
            "see `builders/markers/paper.py`).",
        ]
    variety = markers.get("variety")
    if variety:
        rows += [
            "",
            "Variety of the added wording per pattern and level (added sentences: sentences of a variant that its "
            "clean control does not have; goal: the five most frequent under 10% of them, no sentence opener "
            "twice in one utterance, no indefinite article disagreeing with its noun):",
            "",
            "| Pattern | Level | Added sentences | Distinct | Top-5 share | Most frequent (count) | "
            "Utterances with a repeated opener | Article errors |",
            "| --- | ---: | ---: | ---: | ---: | --- | ---: | ---: |",
        ]
        for pattern, levels in variety.items():
            for level, v in levels.items():
                top = v["top5"][0] if v["top5"] else {"sentence": "", "count": 0}
                rows.append(
                    f"| {pattern} | {level} | {v['added_sentences']:,} | {v['distinct_added_sentences']:,} | "
                    f"{100 * v['top5_share']:.1f}% | {top['sentence']} ({top['count']}) | "
                    f"{v['repeated_opener_utterances']} | {v['article_errors']} |"
                )
    return "\n".join(rows)


def _levels_section() -> str:
    out = []
    for pattern in PATTERNS.values():
        out.append(f"**{pattern.name}** (`{pattern.config}`, {pattern.abbreviation}): {pattern.definition}\n")
        for level, meaning in pattern.levels.items():
            out.append(f"- Level {level}: {meaning}")
        out.append("")
    from talkdem.speech.forms import definitions_table

    out += ["This project's definitions beside the paper's, with the form each utterance draws (`rules-v3`):", ""]
    out.append(definitions_table())
    return "\n".join(out)


def _stats_section(stats: dict[str, Any]) -> str:
    b = stats["benchmark"]
    m = stats["memory_bank"]
    c = stats["benchmark_clean"]
    failed = ", ".join(f"`{k}` ({v})" for k, v in b["failed_checks"].items()) or "none"
    return (
        f"Of the {b['variants']:,} pattern-transformed benchmark instructions, {b['first_attempt_passed']:,} passed "
        f"all checks on the first attempt; {b['regenerated']:,} were regenerated, of which "
        f"{b['second_attempt_passed']:,} passed on the second attempt; {b['third_attempt']:,} were regenerated once "
        f"more, of which {b['third_attempt_passed']:,} passed, yielding {b['verified']:,} verified instructions "
        f"({100 * b['verified_share']:.1f}%). The remaining {b['kept_with_failed_checks']:,} were kept, with their "
        f"failed checks recorded in `verification.failed_checks` (failed checks: {failed}). The "
        f"{c['variants']:,} clean controls: {c['first_attempt_passed']:,} passed on the first attempt, "
        f"{c['kept_with_failed_checks']:,} kept with failed checks. Memory bank ({m['variants']:,} variants): "
        f"{m['first_attempt_passed']:,} passed on the first attempt, {m['verified']:,} verified, "
        f"{m['kept_with_failed_checks']:,} kept with failed checks."
        + (
            " The rules generator composes each utterance from cues the checks look for, so its first-attempt "
            "pass rate says little about the difficulty of the data; the regeneration path matters for LLM "
            "generators (the paper's LLM passed 4,451 of 4,500 on the first attempt)."
            if stats["build"]["generator"] == "rules"
            else ""
        )
    )


def _provenance(info: dict[str, Any]) -> str:
    """Who wrote the utterances: the card must not call an LLM build rule-based, or the reverse."""
    generator, version, seed = info["generator"], info["prompt_version"], info["seed"]
    if generator == "rules":
        return (
            f"**The shipped data was produced by the `rules` generator** (deterministic, rule-based, no language "
            f"model;\nphrase banks `{version}`, build seed {seed}), not by the LLM used in the paper. The LLM "
            "generator and its\nprompts (`builders/prompts/`) are included for rebuilding the data with a language "
            "model (`talkdem build --generator llm`);\na rebuild records its generator and prompt version in every "
            "row. The embedded SmolLM2-135M runs that generator\nbut does not follow the paper's prompts (it "
            "restates their instructions; none of a smoke build's utterances passed\nverification): rebuild with "
            "a 7B-class instruction model."
        )
    return (
        f"**This data was produced by the `{generator}` generator** with the prompt set `{version}` "
        f"(`builders/prompts/`),\nbuild seed {seed}: greedy decoding, seeded sampling for regenerations."
    )


_DEFINITIONS: tuple[tuple[str, str, str], ...] = (
    (
        "Words",
        "spaCy tokens",
        "spaCy `en_core_web_sm` tokens without punctuation or spaces; rates are per 100 such words (our "
        "choice: the paper does not say whether punctuation counts).",
    ),
    (
        "Repair / self-correction rate",
        "Repairs per 100 words; DementiaBank's CHAT retracing annotations",
        "Self-correction cues of the verifier's closed list (`no,` `I mean`, `sorry`, `wait`, `not the`, `or "
        "rather`, `oops`, `actually`, `scratch that`, ...) per 100 words; for CHAT transcripts the `[//]` and"
        " `[///]` retracings.",
    ),
    (
        "Lexical diversity (MTLD)",
        "MTLD (McCarthy and Jarvis 2010)",
        "MTLD with the standard factor threshold 0.72, mean of the forward and backward passes, partial "
        "factor at the end, over lowercased words (no lemmatization, no punctuation; our choice).",
    ),
    (
        "Vague-reference share",
        "Share of vague references",
        "(pronouns + vague nouns) / (nouns + pronouns), vague nouns from a closed list (thing, stuff, "
        "something, one, whatsit, ...). The paper's clean values (vague 0.210, pronoun 0.209) show that its "
        "vague references include pronouns, as ours do.",
    ),
    (
        "Specific-noun rate",
        "Specific nouns per word",
        "Nouns and proper nouns other than the vague nouns, per word.",
    ),
    (
        "Pronoun share",
        "Pronoun use",
        "Pronouns (spaCy `PRON`, possessives included) / (nouns + pronouns).",
    ),
    (
        "Noun rate",
        "Noun use",
        "Nouns and proper nouns per word.",
    ),
    (
        "Discourse markers",
        "Discourse markers (per 100 words)",
        "A closed list (well, so, you know, I mean, like, anyway, anyhow, actually, oh, um, uh, er, okay, "
        "right, you see, sort of, kind of, hmm, now, mind you) counted only where it stands as its own unit, "
        'between the start or punctuation and punctuation ("well, ..." but not "as well"), per 100 words (our'
        " choice of list and boundary rule).",
    ),
    (
        "Parse depth",
        "Parse depth from the spaCy parse",
        "Per sentence, the longest path from the root to a token in dependency arcs (the root is at depth 0);"
        " the mean over the text's sentences (spaCy's sentences; our choice of convention).",
    ),
    (
        "Relevance to task",
        '"Sentence-level cosine similarity to a reference text" with a sentence encoder',
        "Each sentence of the utterance (split after `.`, `!`, `?`) is embedded with all-MiniLM-L6-v2 and "
        "compared with the task's seed instruction (the reference text; our choice); the utterance's "
        'relevance is the mean over its sentences. We read "sentence-level" this way rather than as one '
        "embedding of the whole utterance: the paper's Topic Drift column (0.666, 0.470, 0.379 for one, two "
        "and four or more added sentences) falls as the share of off-task sentences grows, which a "
        "whole-utterance embedding does not reproduce (it gave 0.74 to 0.63). Until issue 14 we embedded the "
        "whole utterance (clean 0.820).",
    ),
)
"""Per marker: (name, what the paper says, what we compute). Shown in the card."""


def _moves(entry: dict[str, Any]) -> str:
    """yes: step by step in the paper's arrow; "as the paper's column" where that column turns back and ours too."""
    from builders.markers.paper import follows_papers_column

    if entry["holds"]:
        return "yes"
    turns_with_the_paper = follows_papers_column(entry["marker"], entry["pattern"], entry["values"])
    return "as the paper's column" if turns_with_the_paper else "NO"


def _definitions() -> str:
    rows = ["| Marker | The paper | Ours |", "| --- | --- | --- |"]
    rows += [f"| {m} | {paper} | {ours} |" for m, paper, ours in _DEFINITIONS]
    return "\n".join(rows)


def _departures(markers: dict[str, Any]) -> str:
    """The paper's non-monotonic columns: what the generator aims at, and how this data moves (from markers.json)."""
    from builders.markers.measures import MARKERS
    from builders.markers.paper import DEPARTURES, LEVEL_KEYS, follows_papers_column

    shipped = {(d["marker"], d["pattern"]): d for d in markers["directions"]}
    lines = ["Where the paper's own column is not monotonic, the data may follow its arrow or its column:", ""]
    for (marker, pattern), why in DEPARTURES.items():
        line = f"- {MARKERS[marker]} ({pattern.replace('_', ' ')}): {why}"
        if entry := shipped.get((marker, pattern)):
            values = entry["values"]
            if entry["holds"]:
                moves = "the paper's arrow, step by step"
            elif follows_papers_column(marker, pattern, values):
                moves = "the paper's own column, step by step"
            else:
                moves = "neither the paper's arrow nor its column"
            chain = " -> ".join(f"{values[k]:.2f}" if abs(values[k]) >= 1 else f"{values[k]:.3f}" for k in LEVEL_KEYS)
            line += f" On this data (clean -> L1 -> L2 -> L3: {chain}) it follows {moves}."
        lines.append(line)
    return "\n".join(lines)


def _sample_page(folder: Path) -> str:
    """A link to the sample page where `talkdem sample-page` wrote it beside the card (else nothing)."""
    if not (folder / "sample.html").is_file():
        return ""
    return (
        "\n**Read a sample:** [`sample.html`](sample.html) is one self-contained page (open it in a browser) "
        "showing, per task, the ALFRED seed, the clean control and the 15 variants side by side, with the words "
        "each pattern adds highlighted, and filters by pattern, level and task type (`talkdem sample-page`).\n"
    )


def _llm_section(stats: dict[str, Any]) -> str:
    """What the LLM path gives and costs: this build's own figures for an LLM build, else the committed sample's."""
    from builders.reporting.llm_stats import sample_card_section
    from talkdem.paths import repo_root

    return sample_card_section(stats, repo_root())


def render_card(stats: dict[str, Any], folder: Path) -> str:
    from builders.selection.retrieval import memory_bank_section

    markers_file = folder / "markers.json"
    if markers_file.is_file():
        markers = json.loads(markers_file.read_text())
        markers_part = (
            f"Computed with `talkdem markers` (spaCy {markers['spacy_version']}, pipeline "
            f"`{markers['pipeline']}`; relevance with all-MiniLM-L6-v2) on the shipped benchmark instructions; "
            f"values are means over the 300 instructions of each cell. The full results are in `markers.json`.\n\n"
            + markers_table(markers)
        )
        markers_part += "\n\n" + _departures(markers)
    else:
        markers_part = "Not computed for this build yet: run `talkdem markers`."
    if validation := validation_section(folder):  # empty until `talkdem validate-dataset` has run
        markers_part += "\n\n#### Independent validation\n\n" + validation
    info = stats["build"]
    counts = stats["counts"]
    return _TEMPLATE.format(
        configs=configs_yaml(),
        instructions=f"{counts['instructions']:,}",
        tasks=counts["tasks"],
        memory_items=f"{counts['memory_items']:,}",
        memory_tasks=counts["memory_tasks"],
        provenance=_provenance(info),
        levels=_levels_section(),
        verification=_stats_section(stats) + "\n\n" + _llm_section(stats),
        markers=markers_part,
        definitions=_definitions(),
        memory_bank=memory_bank_section(folder),
        sample_page=_sample_page(folder),
        prompt_version=f"`{info.get('prompt_version', '')}`",
        candidates=_candidates_text(info, counts["instructions"] + counts["memory_items"]),
        rules_v2=_retired("rules-v2"),
    )


def _retired(name: str) -> str:
    """Where git keeps a retired generator (`talkdem.speech.base.RETIRED`)."""
    from talkdem.speech.base import RETIRED

    commit, path = RETIRED[name]
    return f"`git show {commit}:{path}`"


# Measured on this project's 2-core machine: the ranked build of data/ (25,600 candidates, Qwen2.5-Coder-0.5B)
# took 1 h 57 min with --workers 2 (one thread each; 30 min of it beside a test suite), 0.55 s per candidate and
# thread (the ranking pilot had estimated 0.82 s).
_RANK_SECONDS_PER_CANDIDATE = 0.55


def _candidates_text(info: dict[str, Any], requests: int) -> str:
    """How the kept utterance was chosen among the drawn candidates, from the build's own settings."""
    count = int(info.get("candidates") or 1)
    model = info.get("rank_model")
    if count <= 1:
        return "Each request draws one utterance; a failing one is regenerated (below)."
    hours = requests * count * _RANK_SECONDS_PER_CANDIDATE / 3600
    if model:
        from builders.generation.ranking import model_name

        name = model_name(str(model))
        margin = float(info.get("rank_margin") or 0.0)
        kept = (
            f"the first of them, in draw order, that scores within {margin:g} nats per token of the best is kept "
            "(a margin keeps the generator's variety and drops only the disfluent tail)"
            if margin
            else "the best is kept"
        )
        option = f" --rank-margin {margin:g}" if margin else ""
        return (
            f"Each request draws {count} candidates (each with its own seed); the ones that pass verification are "
            f"scored by `{model}`'s mean log-probability per token and {kept}; its score is in `ranking.score`, "
            f"every passing candidate's in `ranking.scored`. Scoring the {requests * count:,} candidates takes "
            f"about {hours:.1f} hours on one CPU thread (`talkdem build --rank-model {name}{option} --workers N` "
            "spreads the tasks over N processes). "
            "The test suite does not rank again: it replays the recorded choices through the current generator "
            "and verifier (`builders/replay.py`), which writes these files only if every kept utterance is still "
            "a verified candidate of its request at the attempt it records, and it ranks one task with the model "
            "to check that the model makes the same choices (up to near ties, under 0.001 nats per token, where "
            "llama.cpp's last digits may differ between machines)."
        )
    return (
        f"Each request draws {count} candidates (each with its own seed) and keeps the first that passes "
        "verification. **This build is not ranked:** ranking the verified candidates by a language model's mean "
        "log-probability per token (`talkdem build --rank-model qwen2.5-coder-0.5b`; the row's `ranking` field "
        f"then holds the score) is implemented, but costs about {_RANK_SECONDS_PER_CANDIDATE} s per candidate "
        f"on one CPU thread, about {hours:.1f} hours for the {requests * count:,} candidates of this build, "
        "and has not been run; `ranking.score` is null in every row."
    )


_TEMPLATE = """---
license: mit
pretty_name: TALK-Dem
language:
- en
task_categories:
- text-generation
- robotics
tags:
- embodied-ai
- task-planning
- dementia
- human-robot-interaction
- alfred
size_categories:
- 1K<n<10K
{configs}
---

# TALK-Dem

TALK-Dem is a benchmark for robot task planning under dementia-associated communication. Each of
{tasks} household tasks from ALFRED (as curated by REI-Bench) is given as a clean conversational request and as
15 variants exhibiting one of five communication patterns associated with dementia at three intensities:
{instructions} instructions in all. A disjoint memory bank of {memory_items} instructions from {memory_tasks}
held-out tasks, with their resolved interpretations and reference plans, supports retrieval-based mitigation (CARE).

{provenance}
{sample_page}
## Dataset Details

- **Curated by:** the TALK-Dem authors.
- **Language:** English.
- **License:** MIT. Seed tasks come from ALFRED (MIT) through the REI-Bench candidate pool.
- **Source code:** the TALK-Dem repository (`builders/`, `talk_dem.py`; `talkdem build` rebuilds this folder).

## Uses

**Intended:** evaluating and comparing embodied task planners (LLM planners in AI2-THOR/ALFRED) on
instructions with dementia-associated communication patterns; studying mitigation strategies (aware prompts,
chain of thought, in-context learning, instruction rewriting, retrieval from the memory bank); measuring how
planning degrades with pattern intensity.

**Out of scope:** this dataset is **not for clinical use**. It must not be used to diagnose, screen for or
monitor dementia or any other condition, nor to train systems that do. The utterances are synthetic
transformations of crowd-sourced task descriptions, not speech of people living with dementia, and do not
represent any individual or the variety of real communication. It is not a corpus of dementia speech for
linguistic research.

## Dataset Structure

Configs (load with `datasets.load_dataset("<org>/talk-dem", "<config>", split=...)` once the dataset is on the
Hub, where `talkdem push --repo <org>/talk-dem` puts it; `datasets.load_dataset("<this folder>", ...)` for a
local copy; or `talk_dem.load(pattern, level)` with the copy the package carries):

| Config | Splits | Rows |
| --- | --- | --- |
| one per pattern (see below) | `level_1`, `level_2`, `level_3` | 300 per split |
| `clean` | `test` | 300 |
| `all` | `test` | 4,800 (clean and every pattern and level) |
| `memory_bank` | `train` | {memory_items} |
| `tasks` | `benchmark`, `memory` | 300, 100 |

Instruction rows (`clean`, `all` and the five pattern configs): `id` (`task_id:pattern:level`), `task_id`
(ALFRED trial id), `task_type` (class label over the six ALFRED types), `pattern` (class label: `clean` or
the config name), `level` (0 for clean, else 1-3), `instruction` (the utterance), `clean_instruction` (the
clean control it was transformed from), `seed_instruction` (the ALFRED annotation), `pddl_params`
(`object_target`, `parent_target`, `mrecep_target`, `toggle_target`, `object_sliced`; a parameter the task
type does not use is null), `floor_plan`, `scene_objects` (object types present in the AI2-THOR scene),
`verification` (`passed`, `failed_checks`, `attempts`), `generator`, `prompt_version`, `seed` (the
per-request seed, `derive_seed(build_seed, task_id, pattern, level, attempt)`, or the kept candidate's own seed
derived from it), `ranking` (`score`: the ranking model's mean log-probability per token, null when the build
is not ranked; `model`; `candidates` drawn; `passed` verification; `scored`: each passing candidate's `seed` and
`score`, empty when the build is not ranked).

`memory_bank` rows have the same fields plus `interpretation` (one sentence from the gold task specification)
and `reference_plan` (the skill sequence that solves the task). `tasks` rows: `task_id`, `task_set`,
`task_type`, `task_name`, `floor_plan`, `seed_instruction`, `interpretation`, `pddl_params`,
`scene_objects`, `reference_plan`.

### Patterns and levels

Each variant is generated independently from the same clean control; patterns are never mixed.

{levels}
## Dataset Creation

### Source data

300 tasks (50 for each ALFRED task type: pick and place, stack and place, clean and place, heat and place,
cool and place, examine in light) were selected from the REI-Bench candidate pool (ALFRED trials that
Llama-3.1-8B + SayCan completed in AI2-THOR): duplicates removed, then greedy max-min sampling over sentence
embeddings within each type (see `selection/diversity.md`).

{memory_bank}

### Generation

Step 1 conversationalizes each seed instruction into a clean control: a greeting and a request frame around
the seed's own task wording, which is kept verbatim (object names, action words, destinations, state
words). Three seeds do not name their target object (trial_T20190907_215139_316260,
trial_T20190909_005222_878222, trial_T20190911_120324_851568): their clean control adds one plain sentence
naming it ("I'm after the toilet paper."), so that no variant names an object its clean control does not.

Step 2 transforms the clean control with each pattern at each level ({prompt_version}):

- **One speaker per task.** Each task draws a persona by its id (spouse, children, grandchild, sibling, friend,
  former job and a colleague, home town, holiday place, habit, pet, street; 8 to 23 entries per part), so the
  memories and intrusions of its 16 instructions belong to one person and the 300 tasks do not share one biography.
- **Form drawn per utterance** from ranges per level (the table above): the number of sentences, where the
  vague reference or the correction sits, where an intrusion cuts in, how many fillers. No cell has one sentence
  count for all its rows.
- **Typed fills.** Every memory or association frame declares the kinds of object it can take (food, crockery,
  furniture, keepsake, appliance, textile, ...) from a typed lexicon of the AI2-THOR object types, with each
  name's inflection (a/an/some, is/are, it/them), so a frame never takes an object it makes no sense with.
- **Nothing added asks for anything**, names another task's action, or names an object the clean control does
  not; a correction or the late name comes before the closing thanks. Competing and associated objects come
  from the task's own scene list, so no utterance refers to an object absent from the execution environment.

{candidates}

The same build seed gives byte-identical files. The previous phrase banks (`rules-v2`) are retired; git keeps
them ({rules_v2}); what changed and why is below.

#### What changed from `rules-v2`, and why

`rules-v2` (the build behind every run committed before this one) filled a fixed template per cell: every Topic
Drift row had 2, 3 or 5 sentences at Levels 1-3 and every Empty Speech row 1, 2 or 3; with object names masked, the
ten most frequent added sentences made up 67% of Referential Imprecision Level 2 ("The <obj>, I meant the <obj>.");
one stock persona (an aunt, the vicar, jumble sales) spoke in all 300 tasks and frames took any object ("the
grandchildren used to hide behind the butter knife"); 347 of the 900 Topic Drift rows added a second request
("somebody ought to dust the statue"); the variants of three seeds that do not name their target named it for them;
and its validation counted the generator's own cue lists. `rules-v3` draws the form, the speaker and typed fills as
above, and is validated by a separate module that shares no word list with the generator (below, "Independent
validation"). The memory bank was re-selected so that it shares no ALFRED task with the benchmark (above).

### Verification

Every utterance is checked deterministically against the seed task and the scene list: task preservation (each
task verb of the seed, the target object, the destination, the container, the lamp of look-at tasks, and each
state word such as hot/heated, cold/chilled, clean/rinsed, sliced), no added state of another kind, no object
type absent from the scene, ordinary punctuation (no dashes or colons), no two sentences that open with the same
lead-in ("Oh, the name. Oh, the apple."; the ranking model favoured such repeats), and the pattern's structure
(Referential Imprecision: a vague reference before the name, with the level's distance; Object Substitution: a
competing in-scene object first, then a correction; Empty Speech: non-informative speech inside the request,
more at higher levels; Topic Drift: off-task sentences after the complete request mentioning other scene
objects; Intrusion: an off-task thought inside the unfinished request, which then resumes; clean: none of
these). A failing utterance is regenerated up to two more times; one still failing is kept with its failed
checks, so that the benchmark's composition does not depend on removing difficult seeds.

{verification}

### Linguistic markers

Dementia-associated linguistic markers (paper, appendix "Comparison with Real Dementia Speech"), computed by
`talkdem markers` on the shipped benchmark instructions. The paper names each marker and its tools (spaCy for
part-of-speech and syntax, a sentence encoder for relevance, MTLD after McCarthy and Jarvis) but not every
detail; where it is silent we chose, as marked below.

{definitions}

The clean controls are the first check. The paper's clean controls are single sentences (relevance 0.957, no
discourse markers: 0.04 per 100 words); ours were a greeting sentence, the request and often a closing
sentence ("Hi! ... Thanks."), which split the relevance and carried markers ("Oh, hello"). The clean control is
now one sentence, greeting and thanks inside it, with no discourse marker, and half the request frames name no
person (the paper's clean pronoun share is 0.209).

**What differs from the paper's data.** The paper's instructions were written by an LLM from its prompts; ours
by the deterministic `rules` generator from phrase banks, drawn so that each pattern's own markers land near the
paper's (below). The wording still comes from finite banks combined by rule (the variety figures below give their
reach, with object names masked); the clean controls keep the seed's wording verbatim, typos included, where
the paper's LLM may smooth it; relevance stays lower than the paper's in the clean column (greeting and frame inside
the sentence) and so in every Topic Drift cell. The paper's DementiaBank columns (Ctrl, Dem, d, Delta W) need
IRB-gated transcripts and are not reproduced here; `talkdem markers --chat-dir DIR` computes them from a
user-supplied folder.

{markers}

## Bias, Risks, and Limitations

- The variants are synthetic. They reproduce marker-level tendencies reported for dementia speech, not its
  distribution; the patterns are exaggerated at higher levels (more repairs and fillers than in real speech).
- The rules generator draws from finite phrase banks combined by rule: wording repeats across the 4,800
  instructions more than an LLM rewrite would, and planners could learn its cues. Report results per pattern
  and level, and prefer evaluation over training on this data.
- Seed instructions are ALFRED crowd annotations and keep their errors (typos, a few that do not name their
  target object); the verifier only requires what the seed itself names.
- English only, household tasks in AI2-THOR scenes; stereotyped personal details in digressions (family,
  memories) are invented.
- Not for clinical use (see above).

## Citation

```bibtex
@misc{{talkdem2026,
  title  = {{{{TALK-Dem}}: Benchmarking Embodied Task Planning under Dementia-Associated Communication Patterns}},
  author = {{Zhao, Guangxin and Hu, Yiran and Cao, Yuan and Jiang, Chenxi and Yang, Jianfei and Du, Yegang and
            Taki, Yasuyuki and Kitamura, Yoshifumi and Gu, Lin and Zheng, Zhi}},
  year   = {{2026}}
}}
@inproceedings{{shridhar2020alfred,
  title     = {{ALFRED: A Benchmark for Interpreting Grounded Instructions for Everyday Tasks}},
  author    = {{Shridhar, Mohit and Thomason, Jesse and Gordon, Daniel and Bisk, Yonatan and Han, Winson and
               Mottaghi, Roozbeh and Zettlemoyer, Luke and Fox, Dieter}},
  booktitle = {{CVPR}},
  year      = {{2020}}
}}
@misc{{jiang2026reibench,
  title  = {{REI-Bench: Can Embodied Agents Understand Vague Human Instructions in Task Planning?}},
  author = {{Jiang and others}},
  year   = {{2026}}
}}
```

ALFRED is released under the MIT license; its license text is kept with the seed pool. REI-Bench curated the
seed instruction pool.
"""


def write_card(folder: Path, stats: dict[str, Any]) -> list[Path]:
    """The one writer of the card: `folder/README.md` (what `datasets` and the Hub read) and, when `folder` is
    the checkout's `data/`, the same bytes as the repository's `dataset_card.md`. Returns the paths written."""
    from talkdem.files import replace_file
    from talkdem.paths import repo_root

    text = render_card(stats, folder)
    targets = [folder / "README.md"]
    if folder.resolve() == (repo_root() / "data").resolve():
        targets.append(repo_root() / "dataset_card.md")
    for target in targets:
        replace_file(target, text)
    return targets
