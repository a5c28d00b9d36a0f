"""The `talkdem` command: one entry point, one module per subcommand.

Each subcommand module exposes `register(subparsers)`; heavy libraries are imported inside the command
functions, so `talkdem --help` never loads torch, transformers or datasets.
"""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Sequence

from talkdem import __version__
from talkdem.cli import (
    build,
    demo,
    episodes,
    import_inspect,
    leaderboard,
    markers,
    merge,
    models,
    pack,
    parity,
    push,
    replay,
    report,
    retrieval,
    run,
    sample_errors,
    sample_page,
    score,
    select,
    simulate,
    split,
    sweep,
    tasks,
    validate,
    verify,
    verify_run,
    view,
)
from talkdem.cli.stopping import TERMINATED_EXIT, Terminated, stop_on_signals

__all__ = ["build_parser", "main"]

_COMMANDS = (
    tasks,
    select,
    simulate,
    parity,
    demo,
    build,
    replay,
    verify,
    markers,
    retrieval,
    sample_page,
    validate,
    push,
    episodes,
    run,
    split,
    merge,
    pack,
    sweep,
    score,
    import_inspect,
    verify_run,
    report,
    view,
    sample_errors,
    leaderboard,
    models,
)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="talkdem",
        description="TALK-Dem: robot task planning under dementia-associated communication.",
    )
    parser.add_argument("--version", action="version", version=f"talkdem {__version__}")
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for command in _COMMANDS:
        command.register(subparsers)
    return parser


def _describe(exc: BaseException) -> str:
    """One line for an error a user can act on; OSErrors name the file the system call was about."""
    if isinstance(exc, OSError) and exc.strerror:
        target = f": {exc.filename}" if exc.filename else ""
        return f"{exc.strerror}{target}"
    if isinstance(exc, RecursionError):
        return "input nested too deeply to process"
    return str(exc).splitlines()[0] if str(exc) else type(exc).__name__


def _is_server_error(exc: BaseException) -> bool:
    # Looked up only if the served backend was imported: the CLI must not import backends to start.
    module = sys.modules.get("talkdem.llm.backends.openai_compat")
    return module is not None and isinstance(exc, module.EndpointError | module.LoglikelihoodUnsupportedError)


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        with stop_on_signals():
            code: int = args.handler(args)
    except BrokenPipeError:  # `talkdem tasks | head` should end quietly
        return 0
    except KeyboardInterrupt as stop:
        how = "terminated" if isinstance(stop, Terminated) else "interrupted"
        saved = "tasks are saved in the checkpoint" if args.command == "build" else "episodes are saved"
        print(f"talkdem {args.command}: {how} (finished {saved}; run again to resume)", file=sys.stderr)
        return TERMINATED_EXIT if isinstance(stop, Terminated) else 130
    except Exception as exc:
        # Every failure is one line and a non-zero exit; TALKDEM_DEBUG=1 shows the traceback of a bug.
        if os.environ.get("TALKDEM_DEBUG"):
            raise
        expected = isinstance(exc, OSError | ValueError | KeyError | ImportError | RecursionError) or _is_server_error(
            exc
        )
        prefix = "" if expected else f"unexpected {type(exc).__name__} (TALKDEM_DEBUG=1 shows where): "
        print(f"talkdem {args.command}: error: {prefix}{_describe(exc)}", file=sys.stderr)
        return 2
    return code
