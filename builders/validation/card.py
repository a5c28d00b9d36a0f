"""The card's validation section: the paper's table with both marker columns, fluency and masked variety.

Everything is rendered from `validation.json` (`talkdem validate-dataset`); the text that judges a number
(within tolerance, moving as in the paper, meeting a goal) is derived from the numbers, never written by hand,
so it stays true when the data is rebuilt.
"""

from __future__ import annotations

import itertools
import json
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from builders.validation.markers import MARKER_LABELS
from builders.validation.paper import LEVEL_KEYS, RELATIVE_TOLERANCE, moves_as_paper, within
from builders.validation.variety import MIN_ADDED, TOP, TOP_SHARE_GOAL

__all__ = ["DEFINITIONS", "escape_markdown", "validation_markdown", "validation_section"]

_ABBREVIATIONS = {
    "referential_imprecision": "RI",
    "object_substitution": "OS",
    "empty_speech": "ES",
    "topic_drift": "TD",
    "intrusion": "IN",
}
_COLUMNS = ("ours", "independent")
_MARKDOWN_SPECIALS = "\\`*_[]|#"

DEFINITIONS: tuple[tuple[str, str], ...] = (
    ("Words", "spaCy tokens other than punctuation and whitespace; rates are per word or per 100 words."),
    ("Pronoun share", "spaCy `PRON` / (nouns + proper nouns + pronouns): the pronoun ratio of Fraser et al. (2016)."),
    ("Noun rate", "Nouns and proper nouns per word (Fraser et al. 2016); filled pauses mis-tagged as nouns excluded."),
    (
        "Vague-reference share",
        "(pronouns + vague nouns) / (nouns + pronouns); vague nouns: Halliday & Hasan's (1976) general nouns "
        "(thing, stuff, place, person, ...) and placeholder words (whatsit, thingamajig; Enfield 2003), by lemma.",
    ),
    ("Specific-noun rate", "Nouns other than the vague nouns, per word."),
    (
        "Discourse markers",
        "Per 100 words: spaCy interjections (`INTJ` / `intj`) other than politeness markers, greetings, thanks "
        "and answer particles (Fraser 1996); filled pauses; Schiffrin's (1987) and Fraser's (2009) phrasal "
        "markers (you know, I mean, anyway, by the way) anywhere; the connectives of Schiffrin (1987) and "
        "Fraser (1999) (well, so, and, but, now, however, ...) in a sentence's left periphery.",
    ),
    (
        "Repair rate",
        "Per 100 words: clusters of Levelt's (1983) editing terms (I mean, I meant, or rather, sorry, no as an "
        "interjection; oops after Schegloff et al. 1977) within 4 words, plus parsed instant repairs without "
        "an editing term (a noun in apposition to a noun; a second object or subject of the same verb).",
    ),
    (
        "Parse depth",
        "Per spaCy sentence, the most dependency arcs from the root to a word; mean over the sentences.",
    ),
    (
        "MTLD",
        "McCarthy & Jarvis (2010), threshold 0.72, forward and backward passes with partial factors, over "
        "lowercased words (own implementation: the PyPI packages import plotting libraries or `pkg_resources`).",
    ),
    (
        "Relevance",
        "Mean over spaCy's sentences of each sentence's cosine (all-MiniLM-L6-v2) to the task's seed "
        "instruction, the paper's reference text.",
    ),
)


def escape_markdown(text: str) -> str:
    """Text safe inside a Markdown table cell: HTML and Markdown specials escaped, one line."""
    out = text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
    for char in _MARKDOWN_SPECIALS:
        out = out.replace(char, "\\" + char)
    return " ".join(out.split())


def _digits(marker: str) -> int:
    return 1 if marker == "mtld" else 2 if marker in {"repair_rate", "discourse_markers"} else 3


def _value(column: dict[str, Any] | None, key: str, digits: int) -> str:
    if column is None:
        return "-"
    mark = "" if column["within_tolerance"][key] else " ✗"
    return f"{column['values'][key]:.{digits}f}{mark}"


def _markers_table(markers: dict[str, Any]) -> list[str]:
    rows = [
        "| Marker | Pattern | Paper direction | "
        + " | ".join(f"{k.capitalize() if k == 'clean' else 'L' + k}: paper / ours / indep." for k in LEVEL_KEYS)
        + " | Step by step in the paper's direction: paper / ours / indep. | Clean to L3: ours / indep. |",
        "| --- | --- | --- | ---: | ---: | ---: | ---: | --- | --- |",
    ]
    for entry in markers["table"]:
        digits = _digits(entry["marker"])
        cells = [
            f"{entry['paper'][k]:.{digits}f} / {_value(entry['ours'], k, digits)} / "
            f"{_value(entry['independent'], k, digits)}"
            for k in LEVEL_KEYS
        ]
        # The paper's own column is judged by the same rule as ours: where it does not move step by step
        # either, a "NO" in our columns is the paper's shape, not a generator's failure.
        paper_steps = moves_as_paper(entry["direction"], [entry["paper"][k] for k in LEVEL_KEYS])
        steps = " / ".join(
            ["yes" if paper_steps else "no"]
            + ["-" if entry[c] is None else ("yes" if entry[c]["moves_as_paper"] else "NO") for c in _COLUMNS]
        )
        ends = " / ".join(
            "-" if entry[c] is None else ("yes" if entry[c]["clean_to_l3_as_paper"] else "NO") for c in _COLUMNS
        )
        rows.append(
            f"| {MARKER_LABELS[entry['marker']]} | {_ABBREVIATIONS.get(entry['pattern'], entry['pattern'])} | "
            f"{'up' if entry['direction'] > 0 else 'down'} | " + " | ".join(cells) + f" | {steps} | {ends} |"
        )
    return rows


def _label(entry: dict[str, Any]) -> str:
    return f"{MARKER_LABELS[entry['marker']]} ({_ABBREVIATIONS.get(entry['pattern'], entry['pattern'])})"


def _turn(entry: dict[str, Any]) -> str:
    """The first level at which the paper's own column steps against its arrow ("" when none does)."""
    chain = [entry["paper"][k] for k in LEVEL_KEYS]
    for level, (before, after) in enumerate(itertools.pairwise(chain), start=1):
        if entry["direction"] * (after - before) <= 0:
            return f"L{level}"
    return ""


def _markers_verdict(markers: dict[str, Any]) -> list[str]:
    table = markers["table"]
    turns = [f"{_label(e)} at {_turn(e)}" for e in table if _turn(e)]
    lines = []
    for column, name in (("ours", "Ours (`builders/markers`)"), ("independent", "The independent markers")):
        summary = markers[column]
        if summary is None:
            lines.append(f"- {name}: not computed for this folder.")
            continue
        present = [e[column] for e in table if e[column] is not None]
        ends = sum(c["clean_to_l3_as_paper"] for c in present)
        lines.append(
            f"- {name}: **{summary['cells_within_tolerance']} of {summary['cells']} cells** within "
            f"max({100 * RELATIVE_TOLERANCE:.0f}%, floor) of the paper's; {ends} of {len(present)} markers move "
            f"from clean to L3 in the paper's direction, {summary['markers_moving_as_paper']} of "
            f"{summary['markers']} step by step."
        )
    lines.append(
        f"- The paper's own table moves step by step in its direction for {len(table) - len(turns)} of "
        f"{len(table)} markers" + (f"; it turns back for {', '.join(turns)}." if turns else ".")
    )
    away = []
    for entry in markers["table"]:
        independent = entry["independent"]
        if independent is None:
            continue
        label = _label(entry)
        outside = [("clean" if k == "clean" else f"L{k}") for k in LEVEL_KEYS if not independent["within_tolerance"][k]]
        if outside:
            away.append(f"{label}: outside the paper's band at {', '.join(outside)}")
        if not independent["moves_as_paper"]:
            away.append(
                f"{label}: does not move step by step in the paper's direction"
                + ("" if independent["clean_to_l3_as_paper"] else ", not even from clean to L3")
                + (
                    f" (neither does the paper's own column, which turns back at {_turn(entry)})"
                    if _turn(entry)
                    else ""
                )
            )
    if away:
        lines += ["", "Where the independent measures move away from the paper's numbers:", ""]
        lines += [f"- {line}" for line in away]
    apart = []
    for entry in markers["table"]:
        ours, independent = entry["ours"], entry["independent"]
        if ours is None or independent is None:
            continue
        digits = _digits(entry["marker"])
        for k in LEVEL_KEYS:
            a, b = ours["values"][k], independent["values"][k]
            if not within(entry["marker"], a, b):  # the tolerance around our value
                level = "clean" if k == "clean" else f"L{k}"
                label = MARKER_LABELS[entry["marker"]]
                apart.append(
                    f"{label} ({_ABBREVIATIONS.get(entry['pattern'])}) {level}: ours {a:.{digits}f}, "
                    f"independent {b:.{digits}f}"
                )
    if apart:
        lines += [
            "",
            "Where ours and the independent measure disagree by more than the tolerance (our cue lists "
            "count what the literature's definitions do not, or the reverse):",
            "",
        ]
        lines += [f"- {line}" for line in apart]
    return lines


def _fluency_table(fluency: dict[str, Any], order: Sequence[str], ranked_by: Sequence[str] = ()) -> list[str]:
    model = fluency["model"]
    cells = fluency["cells"]
    clean = cells["clean"]["perplexity"]
    rows = [
        f"Fluency under `{model['name']}` ({model['backend']}, GGUF SHA-256 `{model['sha256'][:16]}...`, one "
        "thread; the model that ranks candidates is another): mean per-instruction perplexity (exp of the mean "
        f"negative log-likelihood per token) over the clean controls' ({clean:.1f}). 1.00 is as fluent as "
        "the clean requests.",
    ]
    below = [k for k, v in cells.items() if k != "clean" and v["relative_perplexity"] < 1]
    if below:
        rows[0] += (
            f" {len(below)} of {len(cells) - 1} cells score below the clean controls: per-token perplexity falls "
            "with formulaic and repeated material (fillers, a correction that repeats the object's name, stock "
            "sentences), so a lower figure is not by itself more natural speech. Compare a cell across builds, and "
            "read it beside the variety table."
        )
    baseline = _fluency_baseline(fluency)
    if baseline is not None:
        keys = [k for k in cells if k != "clean" and k in baseline]
        better = [k for k in keys if cells[k]["perplexity"] < baseline[k]["perplexity"]]
        worse = [_cell_name(k) for k in keys if k not in better]
        rows[0] += (
            f" In brackets: the previous build, `rules-v2`, under the same model and clean controls "
            f"(`docs/validation/rules-v2.json`); this build has the lower perplexity in {len(better)} of {len(keys)} "
            f"cells" + (f", not in {', '.join(worse)}" if worse else "") + ". Where `rules-v2` scored lower it "
            "repeated a few stock sentences per cell (its Topic Drift and Intrusion banks), which a language model "
            "predicts well; "
            + (
                f"this build was ranked by `{', '.join(ranked_by)}` (see Generation for the rule), and its "
                "sentences name each task's own people and places, which a language model finds less predictable."
                if ranked_by
                else "this build is not ranked for fluency (see Generation)."
            )
        )
    rows += ["", "| Pattern | L1 | L2 | L3 |", "| --- | ---: | ---: | ---: |"]
    for pattern in order:
        shown = []
        for level in (1, 2, 3):
            key = f"{pattern}:{level}"
            value = cells.get(key)
            text = "-" if value is None else f"{value['relative_perplexity']:.2f}"
            if value is not None and baseline is not None and key in baseline:
                text += f" ({baseline[key]['relative_perplexity']:.2f})"
            shown.append(text)
        rows.append(f"| {_ABBREVIATIONS.get(pattern, pattern)} | {' | '.join(shown)} |")
    return rows


def _cell_name(key: str) -> str:
    pattern, level = key.split(":")
    return f"{_ABBREVIATIONS.get(pattern, pattern)} L{level}"


def _fluency_baseline(fluency: dict[str, Any]) -> dict[str, Any] | None:
    """The rules-v2 fluency cells (committed beside the code), when scored by the same model on another build."""
    from talkdem.paths import repo_root

    path = repo_root() / "docs" / "validation" / "rules-v2.json"
    if not path.is_file():
        return None
    stored = json.loads(path.read_text(encoding="utf-8")).get("fluency")
    if not stored or stored.get("model") != fluency.get("model") or stored["cells"] == fluency["cells"]:
        return None
    cells: dict[str, Any] = stored["cells"]
    return cells


def _counts(counts: dict[str, int]) -> str:
    return ", ".join(f"{k}: {v}" for k, v in sorted(counts.items(), key=lambda kv: int(kv[0])))


def _variety_table(variety: dict[str, Any], order: Sequence[str]) -> list[str]:
    rows = [
        f"Variety of the added sentences with object names masked (`<obj>`): templates = distinct masked added "
        f"sentences; goal: where a cell has at least {MIN_ADDED} added sentences, the {TOP} most frequent cover "
        f"at most {100 * TOP_SHARE_GOAL:.0f}% (✗ where they do not). Inserted: the added sentences that are not "
        "a clean sentence edited (keeping under 60% of every clean sentence's words in order), i.e. what the pattern "
        "put in beside the request; their top-10 share is the stricter reading of the goal. Sentence counts: "
        "instructions per number of sentences.",
        "",
        f"| Pattern | Level | Added | Templates | Top-{TOP} share | Inserted | Inserted templates | "
        f"Inserted top-{TOP} share | Distinct 4-grams | Sentence counts | Most frequent template (count) |",
        "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | --- | --- |",
    ]
    for pattern in order:
        for level in (1, 2, 3):
            v = variety.get(f"{pattern}:{level}")
            if v is None:
                continue
            failing = v["added_sentences"] >= MIN_ADDED and v["top10_share"] > TOP_SHARE_GOAL
            inserted_failing = v["inserted_sentences"] >= MIN_ADDED and v["inserted_top10_share"] > TOP_SHARE_GOAL
            top: dict[str, Any] = v["top10"][0] if v["top10"] else {"sentence": "", "count": 0}
            rows.append(
                f"| {_ABBREVIATIONS.get(pattern, pattern)} | {level} | {v['added_sentences']:,} | "
                f"{v['templates']:,} | {100 * v['top10_share']:.0f}%{' ✗' if failing else ''} | "
                f"{v['inserted_sentences']:,} | {v['inserted_templates']:,} | "
                f"{100 * v['inserted_top10_share']:.0f}%{' ✗' if inserted_failing else ''} | "
                f"{v['distinct_four_grams']:,} ({100 * v['distinct_four_gram_share']:.0f}%) | "
                f"{_counts(v['sentence_counts'])} | {escape_markdown(top['sentence'])} ({top['count']}) |"
            )
    return rows


def validation_markdown(report: dict[str, Any]) -> str:
    """The whole section as Markdown, from a `validation.json` report."""
    from builders.validation.pipeline import provenance_markdown

    order = list(dict.fromkeys(key.split(":")[0] for key in report["variety"] if key != "clean"))
    versions = ", ".join(f"`{v}`" for v in report["prompt_versions"])
    lines = [
        f"Checked by `talkdem validate-dataset` on prompt version {versions} with measures the generator never "
        "imports (`builders/validation/`, held apart by a test): the paper's markers defined from the "
        "literature on spaCy parses, fluency under a model used for nothing else, variety with object names "
        "masked.",
        "",
        provenance_markdown(),
        "",
        "Markers: the paper's value, ours (the generator-side `builders/markers`) and the independent one "
        "(✗: outside max(25%, floor) of the paper's).",
        "",
        *_markers_table(report["markers"]),
        "",
        *_markers_verdict(report["markers"]),
        "",
        "| Independent marker | Definition and source |",
        "| --- | --- |",
        *(f"| {name} | {text} |" for name, text in DEFINITIONS),
        "",
    ]
    if "fluency" in report:
        lines += [*_fluency_table(report["fluency"], order, report.get("ranked_by", [])), ""]
    lines += _variety_table(report["variety"], order)
    return "\n".join(lines)


def validation_section(folder: Path) -> str:
    """The card's section for a dataset folder, rendered from its `validation.json`; empty without one (so a
    card built before the validation ran is unchanged)."""
    path = folder / "validation.json"
    if not path.is_file():
        return ""
    return validation_markdown(json.loads(path.read_text()))
