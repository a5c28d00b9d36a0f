"""The LLM generator: prompt filling and decoding choices, with a recording stub backend (the real model runs in
tests/dataset/test_llm_build.py)."""

from __future__ import annotations

import re

import pytest

import talk_dem
from builders.generation.llm import PROMPTS_DIR, LLMGenerator, room_of, scene_list
from talkdem.llm.interface.requests import GenerateRequest
from talkdem.speech import GenerationRequest
from talkdem.tasks import get_task

POTATO = "trial_T20190909_152050_792044"


class EchoBackend:
    """Returns a fixed utterance per prompt and records the prompts."""

    def __init__(self) -> None:
        self.requests: list[GenerateRequest] = []

    @property
    def prompts(self) -> list[str]:
        return [r.prompt for r in self.requests]

    def generate(self, requests: list[GenerateRequest]) -> list[str]:
        self.requests.extend(requests)
        return [
            f'\n  "Hello, could you put a heated potato on the counter?"\nextra line {i}' for i in range(len(requests))
        ]


def test_sixteen_versioned_prompts() -> None:
    names = {p.stem for p in (PROMPTS_DIR / "v1").glob("*.txt")}
    expected = {"clean"} | {f"{p}_{lvl}" for p in talk_dem.PATTERNS for lvl in talk_dem.LEVELS}
    assert names == expected


def test_paper_prompts_are_verbatim() -> None:
    clean = (PROMPTS_DIR / "v1" / "clean.txt").read_text()
    assert "Begin with a brief, simple, familiar everyday greeting." in clean
    assert "This utterance is a clean conversational control." in clean
    ri1 = (PROMPTS_DIR / "v1" / "referential_imprecision_1.txt").read_text()
    assert "then immediately give the explicit object name {object} as a brief self-clarification." in ri1


def test_prompts_are_filled_and_sent_in_one_batch() -> None:
    backend = EchoBackend()
    gen = LLMGenerator(backend)
    task = get_task(POTATO)
    requests = [GenerationRequest(task, "clean", 0, "", 1)] + [
        GenerationRequest(task, p, lvl, "Hi! Put a heated potato on the counter.", 2)
        for p in talk_dem.PATTERNS
        for lvl in talk_dem.LEVELS
    ]
    outputs = gen.generate(requests)
    assert len(backend.prompts) == 16
    assert outputs[0] == "Hello, could you put a heated potato on the counter?"
    assert "Put a heated potato on the counter." in backend.prompts[0]  # the seed for conversationalization
    assert all("Hi! Put a heated potato on the counter." in p for p in backend.prompts[1:])
    assert not any(re.search(r"\{(clean|object|scene)\}", p) for p in backend.prompts)
    drift = backend.prompts[1 + 3 * list(talk_dem.PATTERNS).index("topic_drift")]
    assert "A kitchen containing only the following items" in drift and "toaster" in drift


def test_prompt_version_names_folder_and_content() -> None:
    version = LLMGenerator(EchoBackend()).prompt_version
    assert re.fullmatch(r"v1\+[0-9a-f]{10}\+text", version)  # the stub constrains nothing: plain text


def test_backend_answer_count_is_checked() -> None:
    class Short:
        def generate(self, requests: list[GenerateRequest]) -> list[str]:
            return []

    with pytest.raises(ValueError, match="completions"):
        LLMGenerator(Short()).generate([GenerationRequest(get_task(POTATO), "clean", 0, "", 1)])


def test_scene_list_matches_the_paper_form() -> None:
    assert room_of("FloorPlan218") == "living room" and room_of("FloorPlan5") == "kitchen"
    assert (
        scene_list("FloorPlan301", ["DeskLamp", "Bed"])
        == "A bedroom containing only the following items:\n\nbed, desk lamp"
    )


def test_first_attempt_is_greedy_and_regenerations_sample_with_their_seed() -> None:
    backend = EchoBackend()
    task = get_task(POTATO)
    LLMGenerator(backend, retry_temperature=0.8).generate(
        [GenerationRequest(task, "clean", 0, "", 11), GenerationRequest(task, "clean", 0, "", 12, attempt=2)]
    )
    first, retry = backend.requests
    assert first.temperature == 0.0 and retry.temperature == 0.8 and retry.seed == 12
    assert first.prompt == retry.prompt


def test_generator_name_records_the_model() -> None:
    class Named(EchoBackend):
        identity = type("Identity", (), {"name": "smollm2-135m-instruct"})()

    assert LLMGenerator(Named()).name == "llm:smollm2-135m-instruct"
    assert LLMGenerator(EchoBackend()).name == "llm"
