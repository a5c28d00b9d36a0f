"""Drive the viewer in headless Chromium: a copy of its page (beside the original, so `data/` resolves) gets a
script that, after load, acts like a reader (dispatching the same events a keyboard and a mouse do), then
writes what it saw into the DOM that `--dump-dom` prints."""

from __future__ import annotations

import html
import json
import re
import subprocess
from pathlib import Path
from typing import Any

from browser_helpers import chromium

BASELINE = Path(__file__).resolve().parent.parent.parent / "results" / "baseline"
COMMITTED = (BASELINE / "qwen2.5-coder-0.5b-vanilla", BASELINE / "qwen2.5-coder-0.5b-care")
"""The committed level-3 runs the browser tests open."""

_FLAGS = (
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
)

_HARNESS = (Path(__file__).parent / "harness.js").read_text(encoding="utf-8")


def drive(page: Path, steps: str, profile: Path, name: str = "driven") -> dict[str, Any]:
    """Open a copy of `page` with `steps` (JavaScript using the harness's helpers, ending in `finish()`) and
    return the `out` object they filled. `profile` is Chromium's user-data folder: reuse it to keep
    localStorage between two visits."""
    text = page.read_text(encoding="utf-8")
    assert "</body>" in text
    copy = page.with_name(f"{name}.html")
    copy.write_text(text.replace("</body>", f"<script>{_HARNESS.replace('STEPS', steps)}</script></body>"), "utf-8")
    result = subprocess.run(
        [
            chromium(),
            *_FLAGS,
            f"--user-data-dir={profile}",
            "--window-size=1500,1000",
            "--virtual-time-budget=30000",
            "--dump-dom",
            copy.as_uri(),
        ],
        capture_output=True,
        text=True,
        timeout=180,
        check=False,
    )
    assert result.returncode == 0, f"chromium failed ({result.returncode}): {result.stderr[-2000:]}"
    found = re.search(r'<pre id="measurements">(.*?)</pre>', result.stdout, re.S)
    assert found, f"the driving script did not finish in Chromium: {result.stdout[-1500:]}"
    data: dict[str, Any] = json.loads(html.unescape(found.group(1)))
    assert "error" not in data, data["error"]
    assert not data.get("timeout"), f"timed out waiting in the page: {data}"
    return data


def index_of(folder: Path) -> dict[str, Any]:
    """The viewer's index (data/index.js) as Python data."""
    text = (folder / "data" / "index.js").read_text(encoding="utf-8")
    payload = text[text.index("= ") + 2 :].rstrip().removesuffix(";")
    data: dict[str, Any] = json.loads(payload)
    return data


def chunk_of(folder: Path, number: int) -> list[dict[str, Any]]:
    text = (folder / "data" / f"chunk-{number:04d}.js").read_text(encoding="utf-8")
    payload = text[text.index(",") + 1 :].rstrip().removesuffix(");")
    data: list[dict[str, Any]] = json.loads(payload)
    return data
