"""Many episodes in flight, one scheduler for every backend.

The scheduler keeps up to `concurrency` episodes (`talkdem.planner.stepping` step machines) in flight. Each
round it collects the one pending request of every episode in flight, stamps it with the episode's slot
(`session`), hands them to the model together (`answer_requests`: one call per kind of request), sends each
episode its answer and starts the next episode in any slot that finished. How a backend uses a round is its
own business: the multi-sequence llama.cpp scorer runs every episode's pending tokens in shared decodes; a
pool of served clients (`ClientPool`) sends the requests to its servers at once; any other backend answers
them one after the other.

Rounds are deterministic: slots are filled in the order the jobs come, requests are answered in slot order,
and episodes finishing in the same round are reported in slot order, so the same command gives the same
sequence of rounds and, with a deterministic backend, the same records.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Iterable, Iterator, Sequence
from concurrent.futures import ThreadPoolExecutor
from typing import Generic, TypeVar

from talkdem.llm.interface.base import BestContinuation, LanguageModel, ModelIdentity, answer_requests
from talkdem.llm.interface.requests import (
    ChoiceRequest,
    GenerateRequest,
    LoglikelihoodRequest,
    ModelRequest,
    ScoreRequest,
)
from talkdem.planner.stepping import EpisodeSteps

__all__ = ["ClientPool", "in_flight"]

Key = TypeVar("Key")
Result = TypeVar("Result")


class _Slot(Generic[Key, Result]):
    __slots__ = ("key", "request", "steps")

    def __init__(self, key: Key, steps: EpisodeSteps[Result], request: ModelRequest) -> None:
        self.key, self.steps, self.request = key, steps, request


def _stamped(request: ModelRequest, session: int) -> ModelRequest:
    if isinstance(request, ChoiceRequest | ScoreRequest):
        return dataclasses.replace(request, session=session)
    return request


def in_flight(
    jobs: Iterable[tuple[Key, Callable[[], EpisodeSteps[Result]]]],
    model: LanguageModel,
    concurrency: int,
) -> Iterator[tuple[Key, Result]]:
    """Run every job's episode, `concurrency` at a time; yield (key, result) as each finishes.

    `jobs` is read lazily (a job is started when a slot is free), so the caller can prepare inputs chunk by
    chunk (a strategy's rewriting) while earlier episodes are still in flight. With a backend that streams
    choices (`LanguageModel.streams_choices`), a choice is handed over as soon as its episode asks and answered
    whenever the backend finishes it; every other request is answered in rounds, all pending ones together.
    """
    if concurrency < 1:
        raise ValueError(f"concurrency must be at least 1, got {concurrency}")
    queue = iter(jobs)
    slots: dict[int, _Slot[Key, Result]] = {}
    submitted: set[int] = set()
    exhausted = False
    while True:
        finished: list[tuple[Key, Result]] = []
        free = [s for s in range(concurrency) if s not in slots]
        while free and not exhausted:
            job = next(queue, None)
            if job is None:
                exhausted = True
                break
            key, start = job
            steps = start()
            try:
                request = next(steps)
            except StopIteration as done:  # an episode that needs nothing from the model
                finished.append((key, done.value))
                continue
            slots[free.pop(0)] = _Slot(key, steps, request)
        yield from finished
        if not slots:
            return
        waiting = [s for s in sorted(slots) if s not in submitted]
        if model.streams_choices:
            for session in waiting:
                request = slots[session].request
                if isinstance(request, ChoiceRequest):
                    model.submit_choice(dataclasses.replace(request, session=session))
                    submitted.add(session)
            waiting = [s for s in waiting if s not in submitted]
        replies: list[tuple[int, object]]
        if waiting:  # a round of everything not streamed
            answers = answer_requests(model, [_stamped(slots[s].request, s) for s in waiting])
            replies = list(zip(waiting, answers, strict=True))
        else:
            replies = list(model.advance_choices())
            submitted.difference_update(session for session, _ in replies)
        for session, answer in replies:
            slot = slots[session]
            try:
                slot.request = slot.steps.send(answer)
            except StopIteration as done:
                del slots[session]
                model.end_session(session)
                yield slot.key, done.value


class ClientPool(LanguageModel):
    """Several clients of one served model answering a round's requests at once, one request per client.

    A session's requests always go to the same client (`session % clients`), so an episode stays on one server
    from its first step to its last; generation requests carry no session and go round the clients in order.
    """

    def __init__(self, clients: Sequence[LanguageModel]) -> None:
        if not clients:
            raise ValueError("a client pool needs at least one client")
        self.clients = list(clients)
        first = self.clients[0]
        self.identity: ModelIdentity = first.identity
        self.supports_loglikelihood = first.supports_loglikelihood
        self.supports_json_schema = first.supports_json_schema
        self._threads = ThreadPoolExecutor(max_workers=len(self.clients))

    def _each(self, requests: Sequence[ModelRequest], client_of: Callable[[int, ModelRequest], int]) -> list[object]:
        futures = [
            self._threads.submit(answer_requests, self.clients[client_of(i, r) % len(self.clients)], [r])
            for i, r in enumerate(requests)
        ]
        return [future.result()[0] for future in futures]

    def best_continuations(self, requests: Sequence[ChoiceRequest]) -> list[BestContinuation]:
        answers = self._each(requests, lambda _, r: r.session if isinstance(r, ChoiceRequest) else 0)
        return [a for a in answers if isinstance(a, BestContinuation)]

    def score_requests(self, requests: Sequence[ScoreRequest]) -> list[list[float]]:
        answers = self._each(requests, lambda _, r: r.session if isinstance(r, ScoreRequest) else 0)
        return [a for a in answers if isinstance(a, list)]

    def best_continuation(self, context: str, continuations: Sequence[str]) -> BestContinuation:
        return self.clients[0].best_continuation(context, continuations)

    def score_continuations(self, context: str, continuations: Sequence[str]) -> list[float]:
        return self.clients[0].score_continuations(context, continuations)

    def loglikelihood(self, requests: Sequence[LoglikelihoodRequest]) -> list[float]:
        return self.clients[0].loglikelihood(requests)

    def generate(self, requests: Sequence[GenerateRequest]) -> list[str]:
        return [str(a) for a in self._each(requests, lambda i, _: i)]

    def token_count(self, text: str) -> int:
        return self.clients[0].token_count(text)

    def run_info(self) -> dict[str, str]:
        return self.clients[0].run_info()

    def close(self) -> None:
        self._threads.shutdown(wait=False, cancel_futures=True)
