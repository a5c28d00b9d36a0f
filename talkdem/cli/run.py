"""`talkdem run`: plan and execute benchmark episodes with an LLM and a mitigation strategy."""

from __future__ import annotations

import argparse
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from talkdem.cli.arguments import folder_path, non_negative_int, positive_int
from talkdem.sim.seam import DEFAULT_MAX_STEPS

if TYPE_CHECKING:
    from talkdem.clarify import ClarifyMode
    from talkdem.instructions import Instruction
    from talkdem.llm.interface.base import LanguageModel
    from talkdem.planner.react import ReActConfig
    from talkdem.planner.saycan import SayCanConfig
    from talkdem.planner.strategies import Strategy

DEFAULT_CLARIFY_BUDGET = 2
"""Questions per episode with `--clarify` (KnowNo and DialFRED ask about that often per task)."""

__all__ = ["DEFAULT_CLARIFY_BUDGET", "ModelLoader", "RunPlan", "StrategyLoader", "plan_run", "register", "run"]


def register(subparsers: Any) -> None:
    parser = subparsers.add_parser("run", help="run the SayCan planner with an LLM and a strategy over episodes")
    parser.add_argument(
        "--model", default="default", help="model name (`talkdem models`), path, model id or served model name"
    )
    from talkdem.llm.interface.registry import BACKENDS  # a light module: backends themselves load lazily
    from talkdem.planner.strategies import STRATEGIES

    parser.add_argument("--backend", default="llamacpp", choices=BACKENDS.names())
    parser.add_argument("--strategy", default="vanilla", choices=STRATEGIES.names())
    parser.add_argument(
        "--conditions", help="comma-separated: clean, PATTERN (all levels) or PATTERN:LEVEL (default: all 16)"
    )
    parser.add_argument(
        "--limit", type=positive_int, help="number of tasks (stratified over task types; default: all 300)"
    )
    parser.add_argument("--out", type=folder_path, help="run directory (default: runs/<model>-<strategy>); resumes")
    parser.add_argument("--max-steps", type=positive_int, default=DEFAULT_MAX_STEPS)
    parser.add_argument("--scoring", choices=["sum", "mean"], default="sum", help="skill score: sum or mean log-prob")
    parser.add_argument(
        "--planner",
        choices=["scoring", "generative", "react"],
        default="scoring",
        help="generative: for chat endpoints without prompt log-likelihoods; react: closed loop (a thought, an "
        "action, the simulator's answer) on any backend",
    )
    parser.add_argument(
        "--thought-tokens",
        type=positive_int,
        default=24,
        metavar="N",
        help="react planner: the token budget of one thought (it also ends at the first sentence end)",
    )
    parser.add_argument(
        "--feedback",
        choices=["mask", "message", "both", "none"],
        default="message",
        help="after a failed skill: message (default, REI-Bench): show the simulator's failure text; mask: do not "
        "offer the skill again until a step succeeds; both; none (LoTa-Bench's default)",
    )
    parser.add_argument(
        "--no-mask-failed", action="store_true", help="(older flag) with --feedback mask or both: do not mask"
    )
    parser.add_argument(
        "--care-order",
        choices=["best_first", "best_last"],
        help="CARE: where the most similar retrieved item goes (default best_last: next to the query)",
    )
    parser.add_argument("--care-dedupe", action="store_true", help="CARE: at most one retrieved item per memory task")
    parser.add_argument(
        "--generation-tokens",
        type=positive_int,
        metavar="N",
        help="CoT / TOCC: token budget of the generated answer / rewrite (default: measured, docs/strategies.md)",
    )
    parser.add_argument(
        "--generation-plain",
        action="store_true",
        help="CoT / TOCC: continue the generation prompt as plain text, as REI-Bench does (default: the model's "
        "chat template)",
    )
    parser.add_argument(
        "--base-url",
        action="append",
        help="openai backend: server URL, e.g. http://127.0.0.1:8080/v1; repeat for several servers of one model "
        "(episodes are spread over them, each episode on one server)",
    )
    parser.add_argument(
        "--model-arg",
        action="append",
        metavar="KEY=VALUE",
        help="a backend constructor option, checked by the backend (e.g. n_ctx=2048 for llamacpp, "
        "tokenizer=NAME or timeout=120 for openai; a bad key lists the backend's own); repeatable",
    )
    parser.add_argument(
        "--tokenizer",
        help="shorthand for --model-arg tokenizer=...: openai backend, scoring planner: the served model's "
        "tokenizer (model name, GGUF file or local Hugging Face tokenizer folder), so prompts split exactly as in "
        "process",
    )
    parser.add_argument(
        "--scoring-api",
        choices=["completions", "sglang"],
        help="shorthand for --model-arg scoring_api=...: openai backend: /v1/completions with echoed "
        "log-probabilities (vLLM, llama-cpp-python; the default) or SGLang's /generate",
    )
    parser.add_argument(
        "--prompt-format",
        choices=["ids", "text"],
        help="shorthand for --model-arg prompt_format=...: completions scoring: token-id prompts, one request per "
        "step (vLLM; the default), or one string per candidate (llama-cpp-python's server)",
    )
    parser.add_argument(
        "--bos",
        choices=["model", "always", "never"],
        help="shorthand for --model-arg add_bos=...: the served tokenizer's BOS rule (model: its own, the "
        "default), for a server started with another rule",
    )
    parser.add_argument(
        "--concurrency",
        type=positive_int,
        default=1,
        metavar="N",
        help="N episodes in flight at once, their model requests answered together each round (llamacpp: "
        "one multi-sequence context; openai: one client each; see docs/performance.md)",
    )
    parser.add_argument(
        "--timeout",
        type=positive_int,
        metavar="SECONDS",
        help="shorthand for --model-arg timeout=...: openai backend: seconds to wait for one answer (default 60; "
        "a large model's step on vLLM may need more)",
    )
    parser.add_argument("--shard", metavar="I/N", help="run only shard I of N (merge the shards with `talkdem merge`)")
    parser.add_argument(
        "--threads",
        type=positive_int,
        help="shorthand for --model-arg threads=...: hf / llamacpp backends: CPU threads",
    )
    parser.add_argument(
        "--log-top", type=non_negative_int, default=0, metavar="N", help="score every skill and log the best N per step"
    )
    parser.add_argument(
        "--cache",
        type=Path,
        metavar="FILE",
        help="SQLite result cache keyed by model identity: a rerun or another strategy reuses computed scores",
    )
    parser.add_argument(
        "--continue-on-new-revision",
        action="store_true",
        help="resume a run started on another code revision (refused otherwise); the header records both",
    )
    parser.add_argument(
        "--clarify",
        choices=["none", "oracle", "in-pattern"],
        default="none",
        help="let the planner ask questions, answered by a simulated person from the task's gold slots: oracle "
        "(clear answers) or in-pattern (spoken under the instruction's own pattern and level); default none",
    )
    parser.add_argument(
        "--clarify-budget",
        type=positive_int,
        metavar="N",
        help=f"with --clarify: questions allowed per episode (default {DEFAULT_CLARIFY_BUDGET}; they do not count "
        "towards --max-steps)",
    )
    parser.add_argument("--no-progress", action="store_true")
    parser.set_defaults(handler=run)


@dataclass(frozen=True)
class RunPlan:
    """What `talkdem run` will do, decided from its arguments alone (no model loaded): every check of the
    arguments is made here, so `talkdem sweep` can validate a whole grid before anything starts."""

    episodes: list[Instruction]
    extra: dict[str, object]
    """The selection (conditions, sample size, shard, threads) recorded in the header."""
    options: dict[str, Any]
    """The backend's constructor options (`--model-arg`, the flags that are shorthand for one, and what the planner
    needs), checked against the backend's own declaration."""
    urls: list[str | None]
    config: SayCanConfig | ReActConfig
    strategy_options: dict[str, object]
    backend_args: dict[str, str | int | float | bool]


def plan_run(args: argparse.Namespace) -> RunPlan:
    """The run `args` describe; a bad combination of arguments is a ValueError naming the flags."""
    from talkdem.planner.react import ReActConfig
    from talkdem.planner.saycan import SayCanConfig
    from talkdem.runs.sampling import select_episodes
    from talkdem.schema import parse_conditions

    conditions = parse_conditions(args.conditions)
    episodes = select_episodes(conditions, args.limit)
    extra: dict[str, object] = {"conditions": [str(c) for c in conditions], "limit": args.limit}
    if args.shard:
        from talkdem.runs.shards import parse_shard, shard_of

        shard = parse_shard(args.shard)
        selected = len(episodes)
        episodes = shard_of(episodes, shard)
        if not episodes:
            # An empty shard would "finish" at once with exit 0, and a merge would then lack nothing it knows of.
            raise ValueError(
                f"--shard {shard}: this shard is empty, the selection has only {selected} episode(s); "
                f"split it into at most {selected} shard(s)"
            )
        extra["shard"] = str(shard)
    options = _backend_options(args)
    if "threads" in options:
        # llama.cpp's kernels split work by thread count, which can move scores in the last digits: the
        # header says how the run was computed (the last sitting's count, when a resume changed it).
        extra["threads"] = options["threads"]
    urls: list[str | None] = list(args.base_url or [None])
    if len(urls) > args.concurrency:
        raise ValueError(
            f"{len(urls)} --base-url but --concurrency {args.concurrency}: give --concurrency at least "
            f"{len(urls)} so that every server gets episodes"
        )
    config: SayCanConfig | ReActConfig
    # A namespace built before the flags existed (a caller's own) asks nothing.
    clarify: ClarifyMode = vars(args).get("clarify", "none")
    budget: int | None = vars(args).get("clarify_budget")
    if clarify == "none" and budget is not None:
        raise ValueError("--clarify-budget applies with --clarify oracle or in-pattern")
    clarify_budget = 0 if clarify == "none" else (budget or DEFAULT_CLARIFY_BUDGET)
    if args.planner == "react":
        if args.log_top or args.no_mask_failed or args.scoring != "sum":
            raise ValueError("--log-top, --no-mask-failed and --scoring are for the SayCan planners, not react")
        config = ReActConfig(
            max_steps=args.max_steps,
            thought_tokens=args.thought_tokens,
            clarify=clarify,
            clarify_budget=clarify_budget,
        )
    else:
        feedback = args.feedback
        if args.no_mask_failed:
            if feedback not in ("mask", "both"):
                raise ValueError(f"--no-mask-failed turns masking off, and --feedback {feedback} does not mask")
            feedback = {"mask": "none", "both": "message"}[feedback]
        config = SayCanConfig.with_feedback(
            feedback,
            max_steps=args.max_steps,
            scoring=args.scoring,
            mode=args.planner,
            log_top=args.log_top,
            clarify=clarify,
            clarify_budget=clarify_budget,
        )
    return RunPlan(
        episodes=episodes,
        extra=extra,
        options=options,
        urls=urls,
        config=config,
        strategy_options=_strategy_args(args),
        backend_args=_backend_args(args, options),
    )


ModelLoader = Callable[..., "LanguageModel"]
"""`load_model(backend, model, **options)`, or a caller's stand-in that keeps models loaded (a Ray actor)."""
StrategyLoader = Callable[..., "Strategy"]
"""`load_strategy(name, **options)`, or a caller's stand-in that keeps strategies built."""


def run(args: argparse.Namespace, *, load: ModelLoader | None = None, strategies: StrategyLoader | None = None) -> int:
    from talkdem.llm.interface.registry import load_model
    from talkdem.planner.strategies import load_strategy
    from talkdem.runs.runner import run_episodes

    plan = plan_run(args)
    load = load or load_model
    if args.cache is not None:
        from talkdem.llm.scoring.cache import open_cache

        open_cache(args.cache).close()  # a bad --cache file fails now, not after the model has loaded
    clients = []
    # A served model gets one client per episode in flight; an in-process model is loaded once and keeps
    # every episode in flight itself (llama.cpp: one sequence each, `sequences`).
    for slot in range(args.concurrency if args.backend == "openai" else 1):
        url = plan.urls[slot % len(plan.urls)]
        clients.append(load(args.backend, args.model, **plan.options, **({"base_url": url} if url else {})))
    if args.cache is not None:
        from talkdem.llm.scoring.cache import CachedLM

        clients = [CachedLM(client, args.cache) for client in clients]
    model = clients[0]
    strategy = (strategies or load_strategy)(args.strategy, **plan.strategy_options)
    if args.log_top:
        import logging

        logging.basicConfig(level=logging.INFO, format="%(message)s")
    planner = "-react" if args.planner == "react" else ""
    asks = f"-clarify-{plan.config.clarify}" if plan.config.clarify != "none" else ""
    name = Path(model.identity.name).name.removesuffix(".gguf")
    out = args.out or Path("runs") / f"{name}{planner}-{args.strategy}{asks}"
    summary = run_episodes(
        plan.episodes,
        model,
        strategy,
        out,
        plan.config,
        extra_config=plan.extra,
        progress=not args.no_progress,
        clients=clients,
        concurrency=args.concurrency,
        backend_args=plan.backend_args,
        new_revision_ok=args.continue_on_new_revision,
    )
    print(
        f"{summary.run_dir}: {summary.ran} episodes run, {summary.skipped} resumed, "
        f"{summary.successes}/{summary.ran} successful this time"
    )
    return 0


def _strategy_args(args: argparse.Namespace) -> dict[str, object]:
    """The strategy's constructor options from its flags; a flag of another strategy is an error."""
    options: dict[str, object] = {}
    care = {"order": args.care_order, "dedupe": args.care_dedupe or None}
    generation = {"max_new_tokens": args.generation_tokens, "chat": False if args.generation_plain else None}
    for owners, flags, names in (
        (("care",), care, "--care-order / --care-dedupe"),
        (("cot", "tocc"), generation, "--generation-tokens / --generation-plain"),
    ):
        given = {k: v for k, v in flags.items() if v is not None}
        if given and args.strategy not in owners:
            raise ValueError(f"{names} apply to --strategy {' or '.join(owners)}, not {args.strategy}")
        options.update(given)
    return options


_SHORTHANDS = {
    "timeout": ("--timeout", "timeout"),
    "tokenizer": ("--tokenizer", "tokenizer"),
    "scoring_api": ("--scoring-api", "scoring_api"),
    "prompt_format": ("--prompt-format", "prompt_format"),
    "bos": ("--bos", "add_bos"),
    "threads": ("--threads", "threads"),
}
"""`talkdem run` flags that set one backend option: {namespace attribute: (flag, option)}."""
_HEADER_ORDER = ("timeout", "tokenizer", "scoring_api", "prompt_format", "add_bos", "chat_template", "threads")
"""The order the options of the older flags were always recorded in (headers written before `--model-arg` list
them so); other options follow in the order given."""
_SCORING_OPTIONS = {"scoring_api": "completions", "prompt_format": "ids", "add_bos": None}
"""The openai backend's options that shape scoring requests, with their defaults: they go with a tokenizer."""


def _backend_options(args: argparse.Namespace) -> dict[str, Any]:
    """The backend's constructor options from `--model-arg` and its shorthand flags, each checked by the backend's
    own declaration, and what the planner needs of the backend."""
    from talkdem.llm.interface.registry import backend_options, backends_with_option, model_args

    backend = args.backend
    if backend != "openai" and args.base_url:
        # About the run (one client per server), not a backend option.
        raise ValueError("--base-url is for --backend openai")
    given = model_args(backend, vars(args).get("model_arg") or [])
    declared = {option.name: option for option in backend_options(backend)}
    if "sequences" in declared and args.concurrency > 1 and "sequences" not in given:
        # The backend keeps one sequence per episode in flight (multi-sequence llama.cpp).
        given["sequences"] = args.concurrency
    for attribute, (flag, name) in _SHORTHANDS.items():
        value = vars(args).get(attribute)
        if value is None:
            continue
        if name not in declared:
            owners = backends_with_option(name)
            plural = "backend" if len(owners) == 1 else "backends"
            raise ValueError(f"{flag} applies to the {' and '.join(owners)} {plural}, not {backend}")
        (parsed,) = model_args(backend, [f"{name}={value}"]).values()
        if name in given and given[name] != parsed:
            shown = declared[name].text(given[name])
            raise ValueError(f"{flag} {value} and --model-arg {name}={shown} disagree: give one")
        given[name] = parsed
    options: dict[str, Any] = dict(given)
    if backend == "openai":
        if "tokenizer" not in options and args.planner in ("scoring", "react") and _local_tokenizer(args.model):
            # `--model` names a local model (catalog name, GGUF, tokenizer folder): its tokenizer is the served one's
            options["tokenizer"] = args.model
        if "tokenizer" in options:
            for name, default in _SCORING_OPTIONS.items():
                options.setdefault(name, default)
        else:
            if args.planner == "scoring":  # react without a tokenizer writes and parses its actions
                raise ValueError(
                    "scoring through a server needs the served model's tokenizer: give --tokenizer "
                    "(a model name, GGUF file or local tokenizer folder), or use --planner generative"
                )
            for name in _SCORING_OPTIONS:  # no tokenizer, no scoring requests: as these options always were
                options.pop(name, None)
    if args.planner == "react" and backend in ("hf", "llamacpp"):
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


def _backend_args(args: argparse.Namespace, options: dict[str, Any]) -> dict[str, str | int | float | bool]:
    """How the model was reached, for the header: plain values only, and a tokenizer given as a file or
    folder by its name alone (a published header names no machine path)."""
    recorded: dict[str, str | int | float | bool] = {}
    for name, value in options.items():
        if name == "tokenizer" and isinstance(value, str):
            recorded[name] = Path(value).name if Path(value).expanduser().exists() else value
        elif name == "add_bos":  # recorded as the flag `--bos` names it (model, always, never), as it always was
            recorded["bos"] = {None: "model", True: "always", False: "never"}[value]
        elif isinstance(value, str | int | float | bool):
            recorded[name] = value
    if args.concurrency > 1:
        recorded["concurrency"] = args.concurrency
    if args.cache is not None:
        recorded["cache"] = True  # the scores are the model's either way; the file is named nowhere
    return recorded
