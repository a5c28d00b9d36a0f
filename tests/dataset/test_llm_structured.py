"""The LLM path end to end on a real model: SmolLM2-135M-Instruct through llama.cpp, its GGUF chat template,
system and user messages, decoding constrained to the answer's JSON schema, strict parsing, verification and
regeneration. A 135M model writes poor utterances; what is asserted is the structure, not the pass rate."""

from __future__ import annotations

import json
import re

import pytest

from builders.build import build_unit_logged
from builders.generation.llm import ECHO_OF_INPUT, ECHO_OF_PROMPT, OUTPUT_FIELD, UNPARSABLE_OUTPUT, LLMGenerator
from builders.reporting.llm_stats import generation_stats
from talkdem.llm.backends.llamacpp import LlamaCppLM
from talkdem.llm.interface.models import FAST_TEST_MODEL
from talkdem.llm.interface.requests import GenerateRequest
from talkdem.speech import GenerationRequest
from talkdem.tasks import get_task

POTATO = "trial_T20190909_152050_792044"
SCHEMA = json.dumps(
    {
        "type": "object",
        "properties": {OUTPUT_FIELD: {"type": "string", "minLength": 1}},
        "required": [OUTPUT_FIELD],
        "additionalProperties": False,
    }
)
OPENING = re.compile(r'\A\{\s*"rewritten_instruction"\s*:\s*"')


@pytest.fixture(scope="module")
def model() -> LlamaCppLM:
    return LlamaCppLM(FAST_TEST_MODEL, threads=1, n_ctx=2048)


@pytest.mark.slow
def test_the_grammar_holds_chat_and_plain_completions_to_the_schema(model: LlamaCppLM) -> None:
    assert model.use_chat_template and model.supports_json_schema
    chat = GenerateRequest(
        "Rewrite as a polite request: put the apple in the fridge.",
        system="You are a rewriter.",
        max_new_tokens=60,
        stop=(),
        json_schema=SCHEMA,
    )
    plain = GenerateRequest(
        "Rewrite as a polite request: put the apple in the fridge.\nAnswer:",
        max_new_tokens=60,
        stop=(),
        chat=False,
        json_schema=SCHEMA,
    )
    free = GenerateRequest("Say hello.", max_new_tokens=8, stop=())
    answers = model.generate([chat, plain, free])
    for answer in answers[:2]:
        assert OPENING.match(answer), answer  # the grammar forces the object's opening whatever the model wants
        try:
            parsed = json.loads(answer)
        except json.JSONDecodeError:
            continue  # cut at max_new_tokens inside the string: a structured answer, unfinished
        assert set(parsed) == {OUTPUT_FIELD} and parsed[OUTPUT_FIELD].strip()
    assert not answers[2].startswith("{"), "without a schema nothing is constrained"
    assert model.generate([chat]) == answers[:1], "greedy: the same answer twice"


@pytest.mark.slow
def test_a_unit_through_the_real_model_is_parsed_verified_and_regenerated(model: LlamaCppLM) -> None:
    generator = LLMGenerator(model, max_new_tokens=80)
    assert generator.prompt_version.endswith("+json")
    task = get_task(POTATO)
    # The clean control as the backend receives it: the paper's role as the system message.
    request = generator.request_for(GenerationRequest(task, "clean", 0, "", 1))
    assert request.system.startswith("You are rewriting") and request.prompt.startswith("Task:")
    rows, log = build_unit_logged(generator, task, 0, patterns=("referential_imprecision",))
    assert [(r["pattern"], r["level"]) for r in rows] == [("clean", 0)] + [
        ("referential_imprecision", i) for i in (1, 2, 3)
    ]
    for row in rows:
        check = row["verification"]
        assert 1 <= check["attempts"] <= 3 and (check["passed"] or check["attempts"] == 3)
        assert row["instruction"].strip()
        if UNPARSABLE_OUTPUT in check["failed_checks"]:
            assert check["failed_checks"] == [UNPARSABLE_OUTPUT]  # no utterance: nothing else was checked
        else:
            assert not row["instruction"].startswith("{"), "a parsed answer is the utterance, not its JSON"
    # every attempt is logged: one per request, attempts counted up for the ones that failed
    for pattern, level in [(r["pattern"], r["level"]) for r in rows]:
        tries = [a for a in log["attempts"] if (a["pattern"], a["level"]) == (pattern, level)]
        assert [a["attempt"] for a in tries] == list(range(1, len(tries) + 1))
        assert all(not a["passed"] for a in tries[:-1])
    known = {UNPARSABLE_OUTPUT, ECHO_OF_INPUT, ECHO_OF_PROMPT}
    stats = generation_stats(rows, [log])
    assert stats["usage"]["generations"] == len(log["attempts"]) and stats["usage"]["seconds"] > 0
    assert stats["usage"]["completion_tokens"] > 0
    reasons = {c for a in log["attempts"] for c in a["failed_checks"]}
    assert all(r in known or re.fullmatch(r"[a-z_]+", r) for r in reasons)
