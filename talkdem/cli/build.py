"""`talkdem build`: generate, verify and write the whole dataset under `data/` (resumable)."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

from talkdem.cli.arguments import folder_path, positive_int

__all__ = ["register"]


def register(subparsers: Any) -> None:
    parser = subparsers.add_parser(
        "build",
        help="rebuild the dataset (4,800 instructions + 1,600 memory items) as Parquet with its card",
    )
    parser.add_argument(
        "--generator",
        default="rules",
        help="rules (default: rules-v3, no LLM; see talkdem/speech) or llm (the paper's prompts on --backend/--model)",
    )
    parser.add_argument("--backend", default="hf", help="LLM backend for --generator llm (hf, llamacpp, vllm, openai)")
    parser.add_argument("--model", default="default", help="model for --generator llm (default: SmolLM2-135M)")
    parser.add_argument("--base-url", help="server URL for --backend openai")
    parser.add_argument("--threads", type=positive_int, help="CPU threads for --backend llamacpp or hf")
    parser.add_argument(
        "--structured-output",
        choices=("json_schema", "json_object", "off"),
        default="json_schema",
        help="--generator llm: answers as JSON where the backend constrains decoding (llamacpp, vllm, openai); "
        "for --backend openai the response_format form (json_object: llama-cpp-python's server); off: plain text",
    )
    parser.add_argument("--prompt-version", default="v1", help="prompt set under builders/prompts/ (default v1)")
    parser.add_argument(
        "--limit", type=positive_int, help="only the first N benchmark and N memory tasks (a smoke build; needs --out)"
    )
    parser.add_argument(
        "--candidates",
        type=positive_int,
        help="candidates the rules generator draws per instruction (default 4); the verified ones are ranked",
    )
    parser.add_argument(
        "--rank-model",
        default="none",
        help="llama.cpp model ranking the verified candidates by mean log-probability per token, 1 thread "
        "(e.g. qwen2.5-coder-0.5b; default none: the first verified candidate is kept)",
    )
    parser.add_argument(
        "--rank-margin",
        type=float,
        default=0.0,
        help="keep the first verified candidate (in draw order) scoring within this many nats per token of the "
        "best (default 0: the best); a margin keeps the generator's variety and drops only the disfluent tail",
    )
    parser.add_argument(
        "--workers",
        type=positive_int,
        default=1,
        help="processes building tasks side by side, each with its own ranking model on one thread (default 1; "
        "the files are the same bytes for any number)",
    )
    parser.add_argument("--seed", type=int, default=0, help="build seed (default 0): same seed, same bytes")
    parser.add_argument("--out", type=folder_path, help="dataset folder (default: data/ or $TALKDEM_DATA_DIR)")
    parser.add_argument("--tasks-dir", type=Path, help="folder holding tasks/*.jsonl (default: data/)")
    parser.add_argument("--checkpoint", type=Path, help="JSONL checkpoint (default: .cache/build/...)")
    parser.add_argument("--no-progress", action="store_true", help="hide the progress bar")
    parser.add_argument(
        "--new-settings",
        action="store_true",
        help="rebuild data/ with settings other than those it was built with (data/build_stats.json)",
    )
    parser.add_argument("--throttle", type=float, default=0.0, help=argparse.SUPPRESS)  # resume tests
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    from builders.build import build
    from talkdem.paths import data_dir, repo_root
    from talkdem.speech import check_generator_name

    check_generator_name(args.generator)  # a retired one (rules-v2) names the commit that has it
    out = args.out or data_dir()
    if args.limit is not None and Path(out).resolve() == (repo_root() / "data").resolve():
        print("talkdem build: --limit writes a partial dataset; give --out FOLDER (not data/)", file=sys.stderr)
        return 2
    if Path(out).resolve() == (repo_root() / "data").resolve() and not args.new_settings:
        changed = _changed_settings(args, Path(out) / "build_stats.json")
        if changed:
            print(
                f"talkdem build: data/ was built with other settings ({changed}); give the same options to "
                "rebuild it, or --new-settings to replace them, or --out FOLDER",
                file=sys.stderr,
            )
            return 2
    generator: Any = args.generator
    if args.generator == "llm":
        if args.workers > 1:
            print(
                "talkdem build: --workers is for the rules generator; --generator llm builds in one process",
                file=sys.stderr,
            )
            return 2
        generator = _llm_generator(args)
    result = build(
        out,
        generator=generator,
        seed=args.seed,
        checkpoint=args.checkpoint,
        tasks_folder=args.tasks_dir,
        progress=not args.no_progress,
        throttle=args.throttle,
        limit=args.limit,
        candidates=args.candidates,
        rank_model=args.rank_model,
        rank_margin=args.rank_margin,
        workers=args.workers,
    )
    if result.resumed_units:
        print(f"resumed {result.resumed_units} finished tasks from the checkpoint", file=sys.stderr)
    print(json.dumps({"folder": str(result.folder), **result.stats}, indent=2))
    return 0


def _llm_generator(args: argparse.Namespace) -> Any:
    from builders.generation.llm import LLMGenerator
    from talkdem.llm.interface.registry import load_model

    options: dict[str, Any] = {"base_url": args.base_url} if args.base_url else {}
    if args.threads is not None:
        options["threads"] = args.threads
    if args.backend == "openai":
        options["structured_output"] = args.structured_output
    backend = load_model(args.backend, args.model, **options)
    return LLMGenerator(backend, version=args.prompt_version, structured=args.structured_output != "off")


def _changed_settings(args: argparse.Namespace, stats_path: Path) -> str:
    """The build settings that differ from those recorded in `stats_path` ("" when none does, or when
    there is no record: a first build)."""
    try:
        recorded = json.loads(stats_path.read_text())["build"]
    except (OSError, ValueError, KeyError):
        return ""
    from builders.generation.ranking import model_name

    rank_model = None if args.rank_model.lower() == "none" else args.rank_model
    recorded_model = recorded.get("rank_model")
    # the record holds the model's full id (backend:name@sha256...); the option its catalogue name
    recorded_name = model_name(str(recorded_model)) if recorded_model else None
    wanted = {
        "--generator": (args.generator, recorded.get("generator")),
        "--seed": (args.seed, recorded.get("seed")),
        "--rank-model": (rank_model, recorded_name),
    }
    if rank_model and recorded_name:
        wanted["--rank-margin"] = (args.rank_margin, recorded.get("rank_margin"))
    if args.candidates is not None:
        wanted["--candidates"] = (args.candidates, recorded.get("candidates"))
    return ", ".join(
        f"{option} {there if there is not None else 'none'} there, {now if now is not None else 'none'} now"
        for option, (now, there) in wanted.items()
        if now != there
    )
