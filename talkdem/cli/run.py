"""`talkdem run`: plan and execute benchmark episodes with an LLM and a mitigation strategy.

The flags build a `talkdem.runs.config.RunConfig`, which `talkdem.runs.plan.run_config` runs: what a run is
lives there, and a sweep builds the same configuration from its spec without this module.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import TYPE_CHECKING, Any

from talkdem.cli.arguments import folder_path, non_negative_int, positive_int

if TYPE_CHECKING:
    from talkdem.runs.config import RunConfig

__all__ = ["REMOVED_FLAGS", "config_of", "register", "run"]

REMOVED_FLAGS: dict[str, tuple[str, str | None, str | None]] = {
    "--tokenizer": ("--model-arg", "tokenizer", None),
    "--scoring-api": ("--model-arg", "scoring_api", None),
    "--prompt-format": ("--model-arg", "prompt_format", None),
    "--bos": ("--model-arg", "add_bos", None),
    "--timeout": ("--model-arg", "timeout", None),
    "--threads": ("--model-arg", "threads", None),
    "--care-order": ("--strategy-arg", "order", None),
    "--care-dedupe": ("--strategy-arg", "dedupe", "true"),
    "--generation-tokens": ("--strategy-arg", "max_new_tokens", None),
    "--generation-plain": ("--strategy-arg", "chat", "false"),
    "--no-mask-failed": ("--feedback none (--feedback message where it followed --feedback both)", None, ""),
}
"""Flags that were shorthand for one backend or strategy option, or for another flag's value: {flag: (its
replacement, the option, the value a switch stood for)}; with no option, the replacement is written out whole.
Still parsed, so that a script using one is told what to write instead."""


class _Removed(argparse.Action):
    """A removed flag: remembered, and refused in one line naming its replacement when the command runs."""

    def __call__(self, parser: Any, namespace: argparse.Namespace, values: Any, option: str | None = None) -> None:
        flag = str(option)
        replacement, key, switch = REMOVED_FLAGS[flag]
        given = switch if switch is not None else values
        instead = f"{replacement} {key}={given}" if key else replacement
        namespace.removed = [*getattr(namespace, "removed", []), f"{flag} was removed: use {instead}"]


def register(subparsers: Any) -> None:
    from talkdem.llm.interface.registry import BACKENDS, DEFAULT_BACKEND  # light: backends themselves load lazily
    from talkdem.planner.strategies import STRATEGIES
    from talkdem.runs.config import (
        CLARIFY_MODES,
        DEFAULT_CLARIFY_BUDGET,
        DEFAULT_THOUGHT_TOKENS,
        FEEDBACKS,
        PLANNERS,
        SCORINGS,
        RunConfig,
    )

    parser = subparsers.add_parser(
        "run",
        help="run the SayCan planner with an LLM and a strategy over episodes",
        description="Plan and execute episodes; a run directory resumes where it stopped.",
    )
    model = parser.add_argument_group("model")
    model.add_argument("--model", default=RunConfig.model, help="`talkdem models` name, path, model id or served name")
    backends = BACKENDS.names()
    model.add_argument("--backend", default=DEFAULT_BACKEND, choices=backends, metavar="NAME", help=", ".join(backends))
    model.add_argument(
        "--model-arg",
        action="append",
        metavar="KEY=VALUE",
        help="a backend option (n_ctx=2048, threads=4; openai: tokenizer=NAME, timeout=120...), "
        "repeatable; a bad key lists the backend's",
    )
    model.add_argument("--base-url", action="append", metavar="URL", help="openai: a server; repeat for several")
    model.add_argument(
        "--concurrency", type=positive_int, default=RunConfig.concurrency, metavar="N", help="episodes in flight"
    )
    model.add_argument("--cache", type=Path, metavar="FILE", help="SQLite score cache keyed by model identity")
    strategy = parser.add_argument_group("strategy")
    strategies = STRATEGIES.names()
    strategy.add_argument(
        "--strategy", default=RunConfig.strategy, choices=strategies, metavar="NAME", help=", ".join(strategies)
    )
    strategy.add_argument(
        "--strategy-arg",
        action="append",
        metavar="KEY=VALUE",
        help="a strategy option (care: order=best_first, dedupe=true; cot, tocc: max_new_tokens=N, chat=false); "
        "repeatable",
    )
    planner = parser.add_argument_group("planner")
    planner.add_argument(
        "--planner",
        choices=PLANNERS,
        default=RunConfig.planner,
        metavar="KIND",
        help="scoring, generative (chat APIs) or react (closed loop)",
    )
    planner.add_argument("--max-steps", type=positive_int, default=RunConfig.max_steps, metavar="N")
    planner.add_argument("--scoring", choices=SCORINGS, default=RunConfig.scoring, help="sum or mean log-prob")
    planner.add_argument(
        "--feedback",
        choices=FEEDBACKS,
        default=RunConfig.feedback,
        metavar="HOW",
        help="after a failed skill: message (its text), mask, both, none",
    )
    planner.add_argument(
        "--thought-tokens",
        type=positive_int,
        default=DEFAULT_THOUGHT_TOKENS,
        metavar="N",
        help="react: tokens per thought",
    )
    planner.add_argument("--log-top", type=non_negative_int, default=0, metavar="N", help="log the best N skills")
    planner.add_argument(
        "--clarify", choices=CLARIFY_MODES, default="none", metavar="MODE", help="none, oracle or in-pattern answers"
    )
    planner.add_argument(
        "--clarify-budget", type=positive_int, metavar="N", help=f"questions per episode ({DEFAULT_CLARIFY_BUDGET})"
    )
    episodes = parser.add_argument_group("episodes")
    episodes.add_argument("--conditions", metavar="LIST", help="clean, PATTERN, PATTERN:LEVEL (default: all 16)")
    episodes.add_argument("--limit", type=positive_int, metavar="N", help="tasks, stratified (default: all 300)")
    episodes.add_argument("--shard", metavar="I/N", help="only shard I of N (`talkdem merge` joins them)")
    episodes.add_argument("--out", type=folder_path, metavar="DIR", help="run directory (resumes)")
    episodes.add_argument(
        "--continue-on-new-revision", action="store_true", help="resume a run started on another code revision"
    )
    episodes.add_argument("--no-progress", action="store_true")
    for flag, (_, _, switch) in REMOVED_FLAGS.items():
        parser.add_argument(flag, action=_Removed, nargs=0 if switch is not None else None, help=argparse.SUPPRESS)
    parser.set_defaults(handler=run)


def config_of(args: argparse.Namespace) -> RunConfig:
    """The run `talkdem run`'s parsed flags describe; a removed flag is a ValueError naming its replacement."""
    from talkdem.runs.config import RunConfig

    removed = getattr(args, "removed", None)
    if removed:
        raise ValueError(removed[0])
    return RunConfig.from_namespace(args)


def run(args: argparse.Namespace) -> int:
    from talkdem.runs.plan import run_config

    summary = run_config(config_of(args))
    print(
        f"{summary.run_dir}: {summary.ran} episodes run, {summary.skipped} resumed, "
        f"{summary.successes}/{summary.ran} successful this time"
    )
    return 0
