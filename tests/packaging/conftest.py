"""Make `wheel_helpers.py` importable: with --import-mode=importlib, test folders are not put on sys.path."""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
