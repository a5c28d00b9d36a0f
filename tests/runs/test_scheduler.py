"""The scheduler that keeps many episodes in flight, with a model whose scores do not depend on the batch.

`HashLM` scores a continuation by a hash of (context, continuation): deterministic, different for every step
of every episode (so plans diverge across tasks and conditions), and the same whatever else is in flight. With
such a model N episodes in flight must give exactly the records of N serial episodes; what the real llama.cpp
batches do is tested in tests/llm/test_llamacpp_sequences.py.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Sequence
from pathlib import Path

import pytest

from talkdem.instructions import Instruction
from talkdem.llm.interface.base import BestContinuation, LanguageModel, ModelIdentity
from talkdem.llm.interface.requests import ChoiceRequest, GenerateRequest, LoglikelihoodRequest
from talkdem.planner.react import ReActConfig
from talkdem.planner.saycan import SayCanConfig
from talkdem.planner.strategies import load_strategy
from talkdem.runs.runner import run_episodes
from talkdem.runs.sampling import select_episodes
from talkdem.runs.scheduler import ClientPool, in_flight
from talkdem.runs.store import HEADER_FILE
from talkdem.schema import parse_conditions


def _score(context: str, continuation: str) -> float:
    digest = hashlib.sha256(f"{context}\x00{continuation}".encode()).digest()
    return -int.from_bytes(digest[:4], "big") / 2**32 * 5 - len(continuation) / 20


class HashLM(LanguageModel):
    """Scores from a hash of the request: no state, no batch effects. Records what each call received."""

    def __init__(self, fail_after: int | None = None) -> None:
        self.identity = ModelIdentity("hash", "hash-test-model", "1")
        self.rounds: list[list[int]] = []
        self.ended: list[int] = []
        self.fail_after = fail_after

    def loglikelihood(self, requests: Sequence[LoglikelihoodRequest]) -> list[float]:
        return [_score(r.context, r.continuation) for r in requests]

    def generate(self, requests: Sequence[GenerateRequest]) -> list[str]:
        return [f"thought {hashlib.sha256(r.prompt.encode()).hexdigest()[:6]}" for r in requests]

    def best_continuations(self, requests: Sequence[ChoiceRequest]) -> list[BestContinuation]:
        self.rounds.append([r.session for r in requests])
        if self.fail_after is not None and len(self.rounds) > self.fail_after:
            raise RuntimeError("the model went away")
        return super().best_continuations(requests)

    def end_session(self, session: int) -> None:
        self.ended.append(session)


EPISODES: list[Instruction] = list(select_episodes(parse_conditions("clean,referential_imprecision:3,intrusion:1"), 4))


def _records(run_dir: Path) -> list[dict[str, object]]:
    records = [json.loads(line) for line in (run_dir / "episodes.jsonl").read_text().splitlines()]
    for record in records:
        record.pop("timing")  # wall-clock seconds: the one field that may differ
    return records


@pytest.mark.parametrize("config", [SayCanConfig.with_feedback("message"), ReActConfig(max_steps=6)])
def test_episodes_in_flight_give_the_records_of_serial_episodes(tmp_path: Path, config: object) -> None:
    strategy = load_strategy("vanilla")
    serial_model, batched_model = HashLM(), HashLM()
    run_episodes(EPISODES, serial_model, strategy, tmp_path / "serial", config, progress=False)  # type: ignore[arg-type]
    run_episodes(
        EPISODES,
        batched_model,
        strategy,
        tmp_path / "batched",
        config,
        progress=False,
        concurrency=5,  # type: ignore[arg-type]
    )
    assert _records(tmp_path / "batched") == _records(tmp_path / "serial")
    # Serial: one request per call. Batched: the model saw several episodes' requests at once, each
    # episode on its own slot, and every episode's end was announced.
    assert {len(r) for r in serial_model.rounds} == {1}
    assert max(len(r) for r in batched_model.rounds) == 5
    assert all(len(set(r)) == len(r) and set(r) <= set(range(5)) for r in batched_model.rounds)
    assert len(batched_model.ended) == len(EPISODES)
    header = json.loads((tmp_path / "batched" / HEADER_FILE).read_text())
    assert header["status"] == "complete"


def test_a_killed_batched_run_resumes_to_the_uninterrupted_records(tmp_path: Path) -> None:
    strategy = load_strategy("vanilla")
    config = SayCanConfig.with_feedback("message")
    run_episodes(EPISODES, HashLM(), strategy, tmp_path / "whole", config, progress=False, concurrency=4)
    with pytest.raises(RuntimeError, match="went away"):
        run_episodes(EPISODES, HashLM(fail_after=25), strategy, tmp_path / "cut", config, progress=False, concurrency=4)
    kept = _records(tmp_path / "cut")
    assert 0 < len(kept) < len(EPISODES)  # finished episodes were written as they finished
    summary = run_episodes(EPISODES, HashLM(), strategy, tmp_path / "cut", config, progress=False, concurrency=3)
    assert summary.skipped == len(kept)
    assert _records(tmp_path / "cut") == _records(tmp_path / "whole")


def test_the_scheduler_fills_free_slots_lazily_and_reports_in_slot_order() -> None:
    started: list[int] = []

    def episode(key: int, steps: int):  # type: ignore[no-untyped-def]
        started.append(key)
        for step in range(steps):
            answer = yield ChoiceRequest(f"{key}:{step}", (" a", " b"))
            assert isinstance(answer, BestContinuation)
        return key

    jobs = ((key, lambda key=key: episode(key, 1 + key % 3)) for key in range(7))
    model = HashLM()
    finished = []
    for key, result in in_flight(jobs, model, concurrency=2):
        assert key == result
        finished.append(key)
        assert len(started) - len(finished) <= 2  # never more than 2 in flight
    assert sorted(finished) == list(range(7))
    assert finished[0] == 0  # 0 needs one step, 1 two: 0 ends first
    with pytest.raises(ValueError, match="concurrency must be at least 1"):
        list(in_flight(iter(()), model, concurrency=0))


def test_a_client_pool_keeps_each_session_on_one_client() -> None:
    clients = [HashLM(), HashLM(), HashLM()]
    pool = ClientPool(clients)
    requests = [ChoiceRequest(f"context {s}", (" a", " b"), session=s) for s in range(6)]
    assert pool.best_continuations(requests) == HashLM().best_continuations(requests)
    assert [sorted(c.rounds) for c in clients] == [[[0], [3]], [[1], [4]], [[2], [5]]]
    pool.close()
