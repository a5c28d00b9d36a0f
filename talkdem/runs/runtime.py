"""Where a sitting of a run computed its numbers: the machine's CPU and the model's libraries.

The same model, prompts and code can score a step differently on two machines: llama-cpp-python is compiled
from source on each one, and the CPU features its build selects (AVX2, AVX512, VNNI, ...) pick different
quantized kernels. A run built over several sittings records each sitting's runtime (`RunHeader.runtimes`), so
that variation between sittings can be traced to a change of machine or build rather than guessed at. Nothing
here names the machine itself (no host name, no paths): run headers are published.
"""

from __future__ import annotations

import platform
from functools import cache
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from talkdem.llm.interface.base import LanguageModel

__all__ = ["add_runtime", "cpu_model", "describe_runtimes", "sitting_runtime"]


@cache
def cpu_model() -> str:
    """The CPU's model name as the operating system reports it ("" when it does not)."""
    try:
        for line in Path("/proc/cpuinfo").read_text(errors="replace").splitlines():
            key, _, value = line.partition(":")
            if key.strip() in ("model name", "Model", "cpu model"):
                return " ".join(value.split())
    except OSError:
        pass
    return platform.processor()


def sitting_runtime(model: LanguageModel) -> dict[str, str]:
    """This process's runtime for `model`: Python, operating system and architecture, CPU model, and what the
    model's backend says computes its numbers (`LanguageModel.runtime`)."""
    return {
        "python": platform.python_version(),
        "platform": f"{platform.system()} {platform.machine()}",
        "cpu": cpu_model(),
        **model.runtime(),
    }


def add_runtime(recorded: tuple[dict[str, str], ...], runtime: dict[str, str]) -> tuple[dict[str, str], ...]:
    """`recorded` with `runtime` added at the end unless it is there already (first sighting order)."""
    return recorded if not runtime or runtime in recorded else (*recorded, dict(runtime))


_MACHINE_KEYS = ("python", "platform", "cpu")


def describe_runtimes(runtimes: tuple[dict[str, str], ...]) -> str:
    """The runtimes of a run in a phrase for a report's run list, one clause per sitting's runtime:
    "AMD EPYC, llama-cpp-python 0.3.36". The build's feature list (`*_system_info`) is left to the scores file;
    "" when the header records none (a served model, or a run written before runtimes were recorded)."""
    clauses = []
    for runtime in runtimes:
        where = runtime.get("cpu") or runtime.get("platform", "")
        libraries = [
            f"{key.replace('_', '-')} {value}"
            for key, value in runtime.items()
            if key not in _MACHINE_KEYS and not key.endswith("_system_info") and value
        ]
        clauses.append(", ".join(part for part in (where, *libraries) if part))
    return "; ".join(clause for clause in clauses if clause)
