"""The metric core imports without evaluate, datasets, torch or transformers (and without scipy)."""

from __future__ import annotations

import subprocess
import sys


def test_core_imports_light() -> None:
    code = (
        "import sys, talkdem.metrics, talkdem.report, talkdem.leaderboard\n"
        "heavy = [m for m in ('evaluate', 'datasets', 'torch', 'transformers', 'scipy', 'matplotlib')"
        " if m in sys.modules]\n"
        "print(','.join(heavy))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == ""
