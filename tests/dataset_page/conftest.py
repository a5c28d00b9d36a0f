"""`browser_helpers.py` (tests/leaderboard), `viewer_browser.py` (tests/viewer) and `tiny_dataset.py`
(tests/selection) are made importable: with --import-mode=importlib test folders are not on sys.path."""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent.parent / "leaderboard"))
sys.path.insert(0, str(Path(__file__).parent.parent / "selection"))
sys.path.insert(0, str(Path(__file__).parent.parent / "viewer"))
sys.path.insert(0, str(Path(__file__).parent))
