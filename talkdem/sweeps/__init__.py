"""Sweeps: a grid of models x strategies x conditions x tasks run as ordinary `talkdem run` directories, in
local processes or on a Ray cluster (`talkdem sweep`)."""

from talkdem.sweeps.spec import SweepRun, SweepSpec, SweepSpecError, load_sweep, select_runs
from talkdem.sweeps.sweep import SweepResult, describe, run_sweep

__all__ = [
    "SweepResult",
    "SweepRun",
    "SweepSpec",
    "SweepSpecError",
    "describe",
    "load_sweep",
    "run_sweep",
    "select_runs",
]
