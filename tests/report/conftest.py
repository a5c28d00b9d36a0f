"""Make `metrics_helpers.py` (in tests/metrics) and `browser_helpers.py` (in tests/leaderboard) importable:
with --import-mode=importlib, test folders are not put on sys.path."""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent.parent / "metrics"))
sys.path.insert(0, str(Path(__file__).parent.parent / "leaderboard"))
