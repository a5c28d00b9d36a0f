"""The Ray actor of a sweep: one per worker, holding its model (and strategies) loaded across every job it is
given, so a model is loaded once per worker, not once per shard.

A job runs its `RunConfig` in the actor's process, through the same code as `talkdem run` (`run_config`; only
the model and strategy loaders are the actor's cached ones), into a scratch folder on the actor's node: seeded
with what the driver holds of the job's run directory, and sent back whole when the job ends (finished or
not), so the driver writes it into the sweep's folders whether or not the nodes share a file system.

No Ray import here: the class is made a Ray actor by `ray.remote` in the driver, and runs unchanged in a test.
"""

from __future__ import annotations

import contextlib
import io
import tempfile
from dataclasses import replace
from pathlib import Path
from typing import Any

from talkdem.runs.config import RunConfig
from talkdem.runs.store import EPISODES_FILE, HEADER_FILE, PACKED_EPISODES_FILE

__all__ = ["EPISODE_FILES", "RUN_FILES", "ShardWorker"]

EPISODE_FILES = (EPISODES_FILE, PACKED_EPISODES_FILE)
"""A run's episodes in either form: a packed run seeds the job packed, and comes back unpacked if it ran."""
RUN_FILES = (HEADER_FILE, *EPISODE_FILES)


class ShardWorker:
    """Runs sweep jobs (run configurations) with models and strategies kept loaded between them."""

    def __init__(self) -> None:
        self._models: dict[str, Any] = {}
        self._strategies: dict[str, Any] = {}
        self._uses: dict[str, int] = {}
        self._current: tuple[str, Path] | None = None
        self.loads = 0
        """Models loaded by this worker (once each, whatever the number of jobs)."""

    def _load(self, backend: str, model: str, **options: Any) -> Any:
        from talkdem.llm.interface.registry import load_model

        identity = repr((backend, model, sorted(options.items())))
        # One run asks for one client per `--concurrency` slot: each slot keeps a client of its own.
        slot = self._uses.get(identity, 0)
        self._uses[identity] = slot + 1
        key = f"{identity}#{slot}"
        if key not in self._models:
            self._models[key] = load_model(backend, model, **options)
            self.loads += 1
        return self._models[key]

    def _strategy(self, name: str, **options: Any) -> Any:
        from talkdem.planner.strategies import load_strategy

        key = repr((name, sorted(options.items())))
        if key not in self._strategies:
            self._strategies[key] = load_strategy(name, **options)
        return self._strategies[key]

    def run_job(self, key: str, config: RunConfig, seed: dict[str, bytes]) -> tuple[str, dict[str, bytes], str]:
        """Run `config` into SCRATCH (seeded with `seed`, the run directory's files); return (key, the run
        directory's files, an error line or "")."""
        from talkdem.runs.plan import run_config

        with tempfile.TemporaryDirectory(prefix="talkdem-sweep-") as scratch:
            target = Path(scratch) / "run"
            if seed:
                target.mkdir()
                for name, data in seed.items():
                    if name in RUN_FILES:
                        (target / name).write_bytes(data)
            self._uses = {}
            self._current = (key, target)
            error = ""
            try:
                with contextlib.redirect_stdout(io.StringIO()):
                    run_config(replace(config, out=target), load=self._load, strategies=self._strategy)
            except Exception as exc:  # sent back as one line: the driver records it and goes on
                error = f"{type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''}"
            finally:
                self._current = None
            files = {name: (target / name).read_bytes() for name in RUN_FILES if (target / name).is_file()}
        return key, files, error

    def model_loads(self) -> int:
        return self.loads

    def progress(self) -> tuple[str, int] | None:
        """(the running job's key, its episodes on disk), or None when idle."""
        from talkdem.sweeps.work import done_episodes

        current = self._current
        return None if current is None else (current[0], done_episodes(current[1]))
