"""Run every benchmark module that exposes `main()`, each in a fresh process.

A fresh process per module keeps one benchmark's thread pools, caches and memory from changing the next
one's timings (CARE's encoder ran after two LLM benchmarks in one process before).
"""

from __future__ import annotations

import importlib
import pkgutil
import subprocess
import sys

import perf


def main() -> None:
    failed = []
    for module_info in sorted(pkgutil.iter_modules(perf.__path__), key=lambda m: m.name):
        if module_info.name.startswith("_"):
            continue
        name = f"perf.{module_info.name}"
        if not hasattr(importlib.import_module(name), "main"):
            continue
        print(f"== {name} ==", flush=True)
        if subprocess.run([sys.executable, "-m", name], check=False).returncode != 0:
            failed.append(name)
    if failed:
        sys.exit(f"perf benchmarks failed: {', '.join(failed)}")


main()
