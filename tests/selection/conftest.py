"""`tiny_dataset.py` is made importable: with --import-mode=importlib test folders are not on sys.path."""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
