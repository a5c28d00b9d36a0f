"""From a `RunConfig` to a run: `plan_run` decides everything the configuration implies before any model is loaded
(the episodes, the backend's options, the planner's settings, what the header records), so a sweep can check a
whole grid first; `run_config` loads the model and the strategy and runs the episodes.

The CLI (`talkdem run`) and a sweep's workers both come here, with a configuration and nothing of the command line.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from talkdem.runs.config import RunConfig

if TYPE_CHECKING:
    from talkdem.instructions import Instruction
    from talkdem.llm.interface.base import LanguageModel
    from talkdem.planner.react import ReActConfig
    from talkdem.planner.saycan import SayCanConfig
    from talkdem.planner.strategies import Strategy
    from talkdem.runs.runner import RunSummary

__all__ = ["ModelLoader", "RunPlan", "StrategyLoader", "plan_run", "run_config"]


@dataclass(frozen=True)
class RunPlan:
    """What a run will do, decided from its configuration alone (no model loaded): every check of the settings
    is made here, so `talkdem sweep` can validate a whole grid before anything starts."""

    episodes: list[Instruction]
    extra: dict[str, object]
    """The selection (conditions, sample size, shard, threads) recorded in the header."""
    options: dict[str, Any]
    """The backend's constructor options (`--model-arg` and what the planner needs), checked against the
    backend's own declaration."""
    urls: list[str | None]
    config: SayCanConfig | ReActConfig
    strategy_options: dict[str, object]
    backend_args: dict[str, str | int | float | bool]


def plan_run(run: RunConfig) -> RunPlan:
    """The run `run` describes; a bad combination of settings is a ValueError naming the flags."""
    from talkdem.planner.react import ReActConfig
    from talkdem.planner.saycan import SayCanConfig
    from talkdem.runs.sampling import select_episodes
    from talkdem.schema import parse_conditions

    run.check()
    conditions = parse_conditions(run.conditions)
    episodes = select_episodes(conditions, run.limit)
    extra: dict[str, object] = {"conditions": [str(c) for c in conditions], "limit": run.limit}
    if run.shard:
        from talkdem.runs.shards import parse_shard, shard_of

        shard = parse_shard(run.shard)
        selected = len(episodes)
        episodes = shard_of(episodes, shard)
        if not episodes:
            # An empty shard would "finish" at once with exit 0, and a merge would then lack nothing it knows of.
            raise ValueError(
                f"--shard {shard}: this shard is empty, the selection has only {selected} episode(s); "
                f"split it into at most {selected} shard(s)"
            )
        extra["shard"] = str(shard)
    options = _backend_options(run)
    if "threads" in options:
        # llama.cpp's kernels split work by thread count, which can move scores in the last digits: the
        # header says how the run was computed (the last sitting's count, when a resume changed it).
        extra["threads"] = options["threads"]
    urls: list[str | None] = list(run.base_urls or [None])
    if len(urls) > run.concurrency:
        raise ValueError(
            f"{len(urls)} --base-url but --concurrency {run.concurrency}: give --concurrency at least "
            f"{len(urls)} so that every server gets episodes"
        )
    config: SayCanConfig | ReActConfig
    if run.planner == "react":
        if run.log_top or run.scoring != "sum":
            raise ValueError("--log-top and --scoring are for the SayCan planners, not react")
        config = ReActConfig(
            max_steps=run.max_steps,
            thought_tokens=run.thought_tokens,
            clarify=run.clarify,
            clarify_budget=run.questions,
        )
    else:
        config = SayCanConfig.with_feedback(
            run.feedback,
            max_steps=run.max_steps,
            scoring=run.scoring,
            mode=run.planner,
            log_top=run.log_top,
            clarify=run.clarify,
            clarify_budget=run.questions,
        )
    return RunPlan(
        episodes=episodes,
        extra=extra,
        options=options,
        urls=urls,
        config=config,
        strategy_options=dict(run.strategy_args),
        backend_args=_backend_args(run, options),
    )


ModelLoader = Callable[..., "LanguageModel"]
"""`load_model(backend, model, **options)`, or a caller's stand-in that keeps models loaded (a Ray actor)."""
StrategyLoader = Callable[..., "Strategy"]
"""`load_strategy(name, **options)`, or a caller's stand-in that keeps strategies built."""


def run_config(
    run: RunConfig, *, load: ModelLoader | None = None, strategies: StrategyLoader | None = None
) -> RunSummary:
    """Plan `run`, load its model (one client per episode in flight for a served one) and its strategy, and run
    every episode not yet in its run directory (default `runs/<model>[-react]-<strategy>[-clarify-MODE]`)."""
    from talkdem.llm.interface.registry import load_model
    from talkdem.planner.strategies import load_strategy
    from talkdem.runs.runner import run_episodes

    plan = plan_run(run)
    load = load or load_model
    if run.cache is not None:
        from talkdem.llm.scoring.cache import open_cache

        open_cache(run.cache).close()  # a bad --cache file fails now, not after the model has loaded
    clients = []
    # A served model gets one client per episode in flight; an in-process model is loaded once and keeps
    # every episode in flight itself (llama.cpp: one sequence each, `sequences`).
    for slot in range(run.concurrency if run.backend == "openai" else 1):
        url = plan.urls[slot % len(plan.urls)]
        clients.append(load(run.backend, run.model, **plan.options, **({"base_url": url} if url else {})))
    if run.cache is not None:
        from talkdem.llm.scoring.cache import CachedLM

        clients = [CachedLM(client, run.cache) for client in clients]
    model = clients[0]
    strategy = (strategies or load_strategy)(run.strategy, **plan.strategy_options)
    if run.log_top:
        import logging

        logging.basicConfig(level=logging.INFO, format="%(message)s")
    planner = "-react" if run.planner == "react" else ""
    asks = f"-clarify-{plan.config.clarify}" if plan.config.clarify != "none" else ""
    name = Path(model.identity.name).name.removesuffix(".gguf")
    out = run.out or Path("runs") / f"{name}{planner}-{run.strategy}{asks}"
    return run_episodes(
        plan.episodes,
        model,
        strategy,
        out,
        plan.config,
        extra_config=plan.extra,
        progress=run.progress,
        clients=clients,
        concurrency=run.concurrency,
        backend_args=plan.backend_args,
        new_revision_ok=run.continue_on_new_revision,
    )


_HEADER_ORDER = ("timeout", "tokenizer", "scoring_api", "prompt_format", "add_bos", "chat_template", "threads")
"""The order these options were always recorded in (headers written when each had a flag of its own list them
so); other options follow in the order given."""
_SCORING_OPTIONS = {"scoring_api": "completions", "prompt_format": "ids", "add_bos": None}
"""The openai backend's options that shape scoring requests, with their defaults: they go with a tokenizer."""


def _backend_options(run: RunConfig) -> dict[str, Any]:
    """The backend's constructor options (`run.model_args`, typed by the backend's own declaration) and what the
    planner needs of the backend."""
    from talkdem.llm.interface.registry import LOCAL_BACKENDS, backend_options

    backend = run.backend
    if backend != "openai" and run.base_urls:
        # About the run (one client per server), not a backend option.
        raise ValueError("--base-url is for --backend openai")
    options: dict[str, Any] = dict(run.model_args)
    declared = {option.name for option in backend_options(backend)}
    if "sequences" in declared and run.concurrency > 1 and "sequences" not in options:
        # The backend keeps one sequence per episode in flight (multi-sequence llama.cpp).
        options["sequences"] = run.concurrency
    if int(options.get("sequences", 1)) > 1 and (run.scoring == "mean" or run.log_top):
        # Only best-skill choices run in the multi-sequence context; every score a run logs or averages comes from
        # the serial context, whose layout the header (`model.scoring`, set by the multi-sequence context) would
        # not name.
        raise ValueError(
            f"--scoring mean and --log-top score one episode at a time on {backend}: run them with --concurrency 1"
            f" (or without --model-arg sequences)"
        )
    if backend == "openai":
        if "tokenizer" not in options and run.planner in ("scoring", "react") and _local_tokenizer(run.model):
            # `--model` names a local model (catalog name, GGUF, tokenizer folder): its tokenizer is the served one's
            options["tokenizer"] = run.model
        if "tokenizer" in options:
            for name, default in _SCORING_OPTIONS.items():
                options.setdefault(name, default)
        else:
            if run.planner == "scoring":  # react without a tokenizer writes and parses its actions
                raise ValueError(
                    "scoring through a server needs the served model's tokenizer: give --model-arg tokenizer=NAME "
                    "(a model name, GGUF file or local tokenizer folder), or use --planner generative"
                )
            for name in _SCORING_OPTIONS:  # no tokenizer, no scoring requests: as these options always were
                options.pop(name, None)
    if run.planner == "react" and backend in LOCAL_BACKENDS:
        # The thought continues the transcript as plain text: wrapped in a chat template it would share no
        # prefix with the scoring context, and every step would run the whole prompt twice.
        if options.get("chat_template", False):
            raise ValueError("--planner react continues the transcript as plain text: drop model arg chat_template")
        options["chat_template"] = False
    first = [name for name in _HEADER_ORDER if name in options]
    return {name: options[name] for name in [*first, *(n for n in options if n not in first)]}


def _local_tokenizer(model: str) -> bool:
    from talkdem.llm.interface.models import get_model

    return get_model(model) is not None or Path(model).expanduser().exists()


def _backend_args(run: RunConfig, options: dict[str, Any]) -> dict[str, str | int | float | bool]:
    """How the model was reached, for the header: plain values only, and a tokenizer given as a file or
    folder by its name alone (a published header names no machine path)."""
    recorded: dict[str, str | int | float | bool] = {}
    for name, value in options.items():
        if name == "tokenizer" and isinstance(value, str):
            recorded[name] = Path(value).name if Path(value).expanduser().exists() else value
        elif name == "add_bos":  # recorded as `bos` (model, always, never), as the flag once named it
            recorded["bos"] = {None: "model", True: "always", False: "never"}[value]
        elif isinstance(value, str | int | float | bool):
            recorded[name] = value
    if run.concurrency > 1:
        recorded["concurrency"] = run.concurrency
    if run.cache is not None:
        recorded["cache"] = True  # the scores are the model's either way; the file is named nowhere
    return recorded
