"""`talkdem run`: plan and execute benchmark episodes with an LLM and a mitigation strategy."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from talkdem.cli.arguments import non_negative_int, positive_int

__all__ = ["register"]


def register(subparsers: Any) -> None:
    parser = subparsers.add_parser("run", help="run the SayCan planner with an LLM and a strategy over episodes")
    parser.add_argument(
        "--model", default="default", help="model name (`talkdem models`), path, model id or served model name"
    )
    from talkdem.llm.registry import BACKENDS  # a light module: backends themselves load lazily
    from talkdem.planner.strategies import STRATEGIES

    parser.add_argument("--backend", default="llamacpp", choices=BACKENDS.names())
    parser.add_argument("--strategy", default="vanilla", choices=STRATEGIES.names())
    parser.add_argument(
        "--conditions", help="comma-separated: clean, PATTERN (all levels) or PATTERN:LEVEL (default: all 16)"
    )
    parser.add_argument(
        "--limit", type=positive_int, help="number of tasks (stratified over task types; default: all 300)"
    )
    parser.add_argument("--out", type=Path, help="run directory (default: runs/<model>-<strategy>); resumes")
    parser.add_argument("--max-steps", type=positive_int, default=30)
    parser.add_argument("--scoring", choices=["sum", "mean"], default="sum", help="skill score: sum or mean log-prob")
    parser.add_argument(
        "--planner",
        choices=["scoring", "generative"],
        default="scoring",
        help="generative: for chat endpoints without prompt log-likelihoods",
    )
    parser.add_argument("--no-mask-failed", action="store_true", help="offer a skill again right after it failed")
    parser.add_argument("--base-url", help="openai backend: server URL, e.g. http://127.0.0.1:8080/v1")
    parser.add_argument("--threads", type=positive_int, help="hf / llamacpp backends: CPU threads")
    parser.add_argument(
        "--log-top", type=non_negative_int, default=0, metavar="N", help="score every skill and log the best N per step"
    )
    parser.add_argument(
        "--cache",
        type=Path,
        metavar="FILE",
        help="SQLite result cache keyed by model identity: a rerun or another strategy reuses computed scores",
    )
    parser.add_argument("--no-progress", action="store_true")
    parser.set_defaults(handler=run)


# Options that mean something to some backends only: given to another backend they would be silently ignored.
_BACKEND_OPTIONS = {"base_url": ("openai",), "threads": ("hf", "llamacpp")}


def run(args: argparse.Namespace) -> int:
    from talkdem.llm.registry import load_model
    from talkdem.planner.saycan import SayCanConfig
    from talkdem.planner.strategies import load_strategy
    from talkdem.runs.runner import run_episodes
    from talkdem.runs.sampling import select_episodes
    from talkdem.schema import parse_conditions

    conditions = parse_conditions(args.conditions)
    episodes = select_episodes(conditions, args.limit)
    options = {name: getattr(args, name) for name in _BACKEND_OPTIONS if getattr(args, name) is not None}
    for name in options:
        if args.backend not in _BACKEND_OPTIONS[name]:
            flag = "--" + name.replace("_", "-")
            raise ValueError(
                f"{flag} applies to the {' and '.join(_BACKEND_OPTIONS[name])} backend(s), not {args.backend}"
            )
    model = load_model(args.backend, args.model, **options)
    if args.cache is not None:
        from talkdem.llm.cache import CachedLM

        model = CachedLM(model, args.cache)
    strategy = load_strategy(args.strategy)
    config = SayCanConfig(
        max_steps=args.max_steps,
        scoring=args.scoring,
        mask_failed=not args.no_mask_failed,
        mode=args.planner,
        log_top=args.log_top,
    )
    if args.log_top:
        import logging

        logging.basicConfig(level=logging.INFO, format="%(message)s")
    out = args.out or Path("runs") / f"{Path(model.identity.name).name.removesuffix('.gguf')}-{args.strategy}"
    summary = run_episodes(
        episodes,
        model,
        strategy,
        out,
        config,
        extra_config={"conditions": [str(c) for c in conditions], "limit": args.limit},
        progress=not args.no_progress,
    )
    print(
        f"{summary.run_dir}: {summary.ran} episodes run, {summary.skipped} resumed, "
        f"{summary.successes}/{summary.ran} successful this time"
    )
    return 0
