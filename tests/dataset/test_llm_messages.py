"""The LLM path without a model: chat messages, structured answers parsed strictly, echo detection, the attempt
log and its statistics, the card fragment and the resumable sample. The backends here are scripted stand-ins
for a model (the real llama.cpp path runs in test_llm_structured.py)."""

from __future__ import annotations

import json
import re
from collections.abc import Callable, Sequence
from pathlib import Path

import pytest

import talk_dem
from builders.build import build, build_unit_logged
from builders.generation.llm import (
    ECHO_OF_INPUT,
    ECHO_OF_PROMPT,
    OUTPUT_FIELD,
    OUTPUT_SCHEMA,
    PROMPTS_DIR,
    UNPARSABLE_OUTPUT,
    LLMGenerator,
    echo_failures,
    parse_structured,
    parse_text,
    split_prompt,
)
from builders.reporting.llm_sample import pick_tasks, run_sample, summarize
from builders.reporting.llm_stats import card_section, generation_stats, sample_card_section
from talkdem.llm.interface.requests import GenerateRequest
from talkdem.speech import GenerationRequest
from talkdem.speech.rules_v3 import RulesV3Generator
from talkdem.tasks import get_task, load_tasks

POTATO = "trial_T20190909_152050_792044"
CLEAN_POTATO = "Hi there, could you put a heated potato on the counter?"


def _source(request: GenerateRequest) -> str:
    """The text a prompt asks to rewrite (the line after its input label)."""
    match = re.search(r"(?:Original instruction|Task description):\n(.*)", request.prompt)
    assert match is not None
    return match.group(1)


class Scripted:
    """Answers with `answer(request, call_number)`; records every request. `supports_json_schema` as given."""

    def __init__(self, answer: Callable[[GenerateRequest, int], str], structured: bool = True) -> None:
        self.answer = answer
        self.supports_json_schema = structured
        self.requests: list[GenerateRequest] = []

    def generate(self, requests: Sequence[GenerateRequest]) -> list[str]:
        out = [self.answer(r, len(self.requests) + i) for i, r in enumerate(requests)]
        self.requests.extend(requests)
        return out

    def token_count(self, text: str) -> int:
        return len(text.split())


def _json(text: str) -> str:
    return json.dumps({OUTPUT_FIELD: text})


# --- messages -------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("path", sorted(PROMPTS_DIR.glob("v1/*.txt")), ids=lambda p: p.stem)
def test_every_prompt_splits_into_the_role_and_the_task_losing_no_word(path: Path) -> None:
    text = path.read_text()
    system, user = split_prompt(text)
    assert system.startswith("You are ") and "Task:" not in system
    assert user.startswith("Task:") and user.rstrip().endswith("Return only the rewritten instruction.")
    assert (system + " " + user).split() == text.split()[1:]  # all but the "Role:" header


def test_a_prompt_without_the_layout_is_one_user_message() -> None:
    assert split_prompt("Rewrite this.\n\nOutput:\nReturn it.") == ("", "Rewrite this.\n\nOutput:\nReturn it.")


def test_requests_are_system_and_user_messages_and_plain_completions_keep_both() -> None:
    gen = LLMGenerator(Scripted(lambda r, n: _json("x")))
    request = gen.request_for(GenerationRequest(get_task(POTATO), "topic_drift", 2, CLEAN_POTATO, 7))
    system, user = request.messages()
    assert system == {"role": "system", "content": request.system} and system["content"].startswith("You are an")
    assert user["role"] == "user" and CLEAN_POTATO in user["content"] and "Scene:" in user["content"]
    assert request.completion_text() == f"{request.system}\n\n{request.prompt}"
    one = LLMGenerator(Scripted(lambda r, n: ""), system_message=False).request_for(
        GenerationRequest(get_task(POTATO), "topic_drift", 2, CLEAN_POTATO, 7)
    )
    assert one.system == "" and one.messages() == [{"role": "user", "content": one.prompt}]
    assert one.prompt.startswith("Role:")


def test_the_schema_is_sent_only_to_backends_that_constrain_decoding() -> None:
    task = get_task(POTATO)
    structured = LLMGenerator(Scripted(lambda r, n: _json("x")))
    plain = LLMGenerator(Scripted(lambda r, n: "x", structured=False))
    forced_off = LLMGenerator(Scripted(lambda r, n: "x"), structured=False)
    request = GenerationRequest(task, "clean", 0, "", 1)
    assert json.loads(structured.request_for(request).json_schema) == OUTPUT_SCHEMA
    assert plain.request_for(request).json_schema == "" and forced_off.request_for(request).json_schema == ""
    assert structured.prompt_version.endswith("+json") and plain.prompt_version.endswith("+text")
    # the output form is part of the version, so rows of the two forms never share one
    assert structured.prompt_version.split("+")[1] != plain.prompt_version.split("+")[1]


def test_generate_request_rejects_a_schema_that_is_not_a_json_object() -> None:
    with pytest.raises(ValueError, match="json_schema"):
        GenerateRequest("p", json_schema="{not json")
    with pytest.raises(ValueError, match="JSON object"):
        GenerateRequest("p", json_schema="[1, 2]")
    assert GenerateRequest("p", json_schema='{"type": "object"}').schema() == {"type": "object"}


# --- parsing and echoes -----------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("output", "parsed"),
    [
        ('{"rewritten_instruction": "Hi, put the mug away."}', "Hi, put the mug away."),
        ('  {"rewritten_instruction": "Hi,\\n put   the mug away."}\n', "Hi, put the mug away."),
        ('{"rewritten_instruction": ""}', None),
        ('{"rewritten_instruction": "   "}', None),
        ('{"rewritten_instruction": "Hi", "note": "x"}', None),
        ('{"instruction": "Hi"}', None),
        ('{"rewritten_instruction": ["Hi"]}', None),
        ('["Hi"]', None),
        ('{"rewritten_instruction": "Hi, put the mug', None),  # cut at max_new_tokens
        ('Sure! {"rewritten_instruction": "Hi"}', None),
        ("Hi, put the mug away.", None),
    ],
)
def test_structured_answers_are_parsed_strictly(output: str, parsed: str | None) -> None:
    assert parse_structured(output) == parsed


def test_plain_text_takes_the_first_line_that_is_not_a_label() -> None:
    assert parse_text('\n  "Hi, put the mug away."\nSecond line') == "Hi, put the mug away."
    assert parse_text("Here is the rewritten instruction:\n\nHi, put the mug away.") == "Hi, put the mug away."
    assert parse_text("   \n ") == ""


def test_echoes_of_the_input_and_of_the_prompt_are_found() -> None:
    gen = LLMGenerator(Scripted(lambda r, n: ""))
    request = GenerationRequest(get_task(POTATO), "referential_imprecision", 2, CLEAN_POTATO, 1)
    prompt = gen.prompt(request)
    assert echo_failures("hi there could you put a HEATED potato on the counter", CLEAN_POTATO, prompt) == (
        ECHO_OF_INPUT,
    )
    assert echo_failures("Return only the rewritten instruction.", CLEAN_POTATO, prompt) == (ECHO_OF_PROMPT,)
    assert ECHO_OF_PROMPT in echo_failures(f"Target object: potato. {CLEAN_POTATO}", CLEAN_POTATO, prompt)
    honest = "Hi there, could you put that hot thing on the counter? The potato, I mean."
    assert echo_failures(honest, CLEAN_POTATO, prompt) == ()


def test_no_rules_utterance_counts_as_an_echo() -> None:
    # The detector must not fail honest rewrites: every utterance of the rules generator for six tasks
    # (one per task type) against its own prompt.
    rules, gen = RulesV3Generator(), LLMGenerator(Scripted(lambda r, n: ""))
    for task in pick_tasks(1):
        clean = rules.generate([GenerationRequest(task, "clean", 0, "", 3)])[0]
        requests = [GenerationRequest(task, "clean", 0, "", 3)] + [
            GenerationRequest(task, p, lvl, clean, 5) for p in talk_dem.PATTERNS for lvl in talk_dem.LEVELS
        ]
        for request, text in zip(requests, rules.generate(requests), strict=True):
            assert echo_failures(text, gen.source(request), gen.prompt(request)) == (), (request.pattern, text)


# --- attempts, failure reasons and statistics ----------------------------------------------------------------
def _three_attempt_answers(rules: RulesV3Generator, task_id: str) -> Callable[[GenerateRequest, int], str]:
    """Attempt 1 of every variant echoes its input, attempt 2 is cut-off JSON, attempt 3 is a good rewrite (the
    rules generator's, at the same cell); clean controls are good at once."""
    task = get_task(task_id)

    def answer(request: GenerateRequest, call: int) -> str:
        source = _source(request)
        cell = _cell_of(request)
        if cell == ("clean", 0):
            return _json(rules.generate([GenerationRequest(task, "clean", 0, "", 3)])[0])
        if request.temperature == 0.0:
            return _json(source)
        if request.seed % 2 == 0 and not _seen(request):
            return '{"rewritten_instruction": "Hi, could you'
        return _json(rules.generate([GenerationRequest(task, cell[0], cell[1], source, 5)])[0])

    seen: set[tuple[str, int]] = set()

    def _seen(request: GenerateRequest) -> bool:
        key = _cell_of(request)
        found = key in seen
        seen.add(key)
        return found

    return answer


def _cell_of(request: GenerateRequest) -> tuple[str, int]:
    for path in sorted(PROMPTS_DIR.glob("v1/*.txt")):
        system, user = split_prompt(path.read_text())
        head = user.split("\n\n")[1][:80]
        if request.system == system and head in request.prompt:
            name = path.stem
            if name == "clean":
                return "clean", 0
            pattern, level = name.rsplit("_", 1)
            return pattern, int(level)
    raise AssertionError("no prompt matches the request")


def test_echoes_and_unparsable_answers_fail_are_regenerated_and_counted_per_attempt() -> None:
    rules = RulesV3Generator()
    backend = Scripted(_three_attempt_answers(rules, POTATO))
    gen = LLMGenerator(backend)
    rows, log = build_unit_logged(gen, get_task(POTATO), 0)
    variants = [r for r in rows if r["pattern"] != "clean"]
    first = [a for a in log["attempts"] if a["attempt"] == 1 and a["pattern"] != "clean"]
    assert len(first) == 15 and all(not a["passed"] and a["failed_checks"][0] == ECHO_OF_INPUT for a in first)
    second = [a for a in log["attempts"] if a["attempt"] == 2]
    assert len(second) == 15
    cut = [a for a in second if UNPARSABLE_OUTPUT in a["failed_checks"]]
    # an unparsable answer is no utterance: the verifier is not run on it
    assert cut and all(a["failed_checks"] == [UNPARSABLE_OUTPUT] for a in cut)
    stats = generation_stats(rows, [log])
    attempts = stats["attempts"]
    assert attempts["1"] == {
        "generated": 15,
        "passed": 0,
        "failed_by_group": {"echo": 15},
        "failed_checks": attempts["1"]["failed_checks"],
    }
    assert attempts["1"]["failed_checks"][ECHO_OF_INPUT] == 15
    assert attempts["2"]["failed_by_group"].get("unparsable", 0) == len(cut)
    assert attempts["3"]["generated"] == 15 - attempts["2"]["passed"]
    v = stats["variants"]
    assert v["first_attempt_passed"] == 0 and v["regenerated"] == 15
    assert v["second_attempt_passed"] + v["third_attempt_passed"] + v["kept_with_failed_checks"] == 15
    assert v["second_attempt_passed"] == attempts["2"]["passed"]
    assert sum(p["variants"] for p in stats["by_pattern"].values()) == 15
    kept = [r for r in variants if not r["verification"]["passed"]]
    assert v["kept_with_failed_checks"] == len(kept)
    usage = stats["usage"]
    assert usage["generations"] == len(backend.requests) == len(log["attempts"])
    assert usage["utterances"] == 16 and usage["prompt_tokens"] > 0 and usage["seconds"] >= 0
    assert stats["output_form"] == ["json"] and stats["tasks"] == 1


def test_the_card_fragment_reports_the_attempts_and_escapes_what_it_embeds() -> None:
    backend = Scripted(_three_attempt_answers(RulesV3Generator(), POTATO))
    rows, log = build_unit_logged(LLMGenerator(backend), get_task(POTATO), 0)
    stats = generation_stats(rows, [log])
    shown = [{**rows[1], "instruction": "a | b <script>"}]
    text = card_section(stats, "Measured here.", shown)
    assert text.startswith("### What `talkdem build --generator llm` gives and costs")
    assert "Of 15 pattern variants, 0/15 (0%) passed every check on the first attempt" in text
    assert "| 1 | 15 | 0/15 (0%) | 0 | 15 | 0 |" in text
    assert "a \\| b &lt;script&gt;" in text and "<script>" not in text
    assert f"`{ECHO_OF_INPUT}` (15)" in text


def test_the_card_takes_an_llm_builds_own_figures_else_the_committed_sample(tmp_path: Path) -> None:
    assert "Not measured" in sample_card_section({}, tmp_path)
    backend = Scripted(_three_attempt_answers(RulesV3Generator(), POTATO))
    rows, log = build_unit_logged(LLMGenerator(backend), get_task(POTATO), 0)
    stats = generation_stats(rows, [log])
    assert "Measured on this build." in sample_card_section({"generation": stats}, tmp_path)
    summary = tmp_path / "data" / "llm_sample" / "summary.json"
    summary.parent.mkdir(parents=True)
    shown = [{**rows[i], "instruction": f"example {i}"} for i in (1, 2, 4, 5)]  # two patterns, two rows each
    summary.write_text(json.dumps({"stats": stats, "context": "On a sample.", "examples": shown}))
    section = sample_card_section({}, tmp_path)
    assert "On a sample." in section
    assert [i for i in (1, 2, 4, 5) if f"example {i} |" in section] == [1, 4], "one example per pattern"


# --- the build and the sample ----------------------------------------------------------------------------------
def test_an_llm_build_records_attempts_and_costs_in_build_stats_and_card(tmp_path: Path) -> None:
    def answer(request: GenerateRequest, call: int) -> str:
        if "Task description:" in request.prompt:  # the clean control: a greeting and the seed
            return _json(f"Hello, could you {_source(request)[0].lower()}{_source(request)[1:]}")
        return _json(_source(request)) if request.temperature == 0.0 else "{}"

    gen = LLMGenerator(Scripted(answer), name="llm:scripted")
    result = build(tmp_path / "out", generator=gen, checkpoint=tmp_path / "c.jsonl", progress=False, limit=1)
    stats = json.loads((tmp_path / "out" / "build_stats.json").read_text())
    generation = stats["generation"]
    assert generation["attempts"]["1"]["failed_by_group"] == {"echo": 15}
    assert generation["attempts"]["3"]["failed_by_group"] == {"unparsable": 15}
    assert generation["variants"]["kept_with_failed_checks"] == 15 == stats["benchmark"]["kept_with_failed_checks"]
    card = (tmp_path / "out" / "README.md").read_text()
    assert "Measured on this build." in card and "| 3 | 15 | 0/15 (0%) | 15 | 0 | 0 |" in card
    assert result.stats["generation"] == generation


def test_the_sample_picks_every_task_type_and_resumes(tmp_path: Path) -> None:
    picked = pick_tasks(2)
    types = [t.task_type for t in picked]
    assert len(picked) == 12 and len(set(types)) == 6 and all(types.count(t) == 2 for t in types)
    assert types[:6] == types[6:], "interleaved: a run stopped after six tasks has every task type"
    benchmark = load_tasks("benchmark")
    first_of_type = {t.task_type: t for t in reversed(benchmark)}
    assert {t.task_type: t for t in reversed(picked)} == first_of_type
    gen = LLMGenerator(Scripted(lambda r, n: _json(_source(r))), name="llm:scripted")
    tasks = pick_tasks(1)[:2]
    assert run_sample(gen, tasks, tmp_path) == 2
    assert run_sample(gen, tasks, tmp_path) == 0, "finished units are not built again"
    with pytest.raises(ValueError, match="checkpoint of another build"):
        run_sample(gen, pick_tasks(1)[:3], tmp_path)
    summary = summarize(tmp_path, tmp_path / "summary", model_sha256="ab" * 32)
    assert summary["sample"]["tasks_done"] == 2 and summary["sample"]["tasks_planned"] == 2
    assert summary["stats"]["variants"]["variants"] == 30
    patterns = {e["pattern"] for e in summary["examples"]}
    assert patterns == {"clean", *talk_dem.PATTERNS}
    assert all(len([e for e in summary["examples"] if e["pattern"] == p]) == 2 for p in patterns)
    markdown = (tmp_path / "summary" / "summary.md").read_text()
    assert "2 of 2 benchmark tasks" in markdown and "abababababababab" in markdown
