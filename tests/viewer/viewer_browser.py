"""Drive the viewer in headless Chromium: a copy of its page (beside the original, so `data/` resolves) gets a
script that, after load, acts like a reader (dispatching the same events a keyboard and a mouse do), then
writes what it saw into the DOM that `--dump-dom` prints."""

from __future__ import annotations

import html
import json
import re
import subprocess
import tempfile
import threading
import time
from pathlib import Path
from typing import Any

from browser_helpers import chromium

PAPER = Path(__file__).resolve().parent.parent.parent / "results" / "paper"
COMMITTED = (PAPER / "qwen2.5-coder-0.5b-vanilla", PAPER / "qwen2.5-coder-0.5b-care")
"""The committed runs the viewer tests open: the default model under Vanilla and CARE, all 16 conditions."""

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


def _dump_dom(command: list[str], timeout: float = 180) -> str:
    """Chromium's `--dump-dom` output. On a busy machine headless Chromium now and then prints the DOM and
    then does not exit: once the document is complete it gets 10 s to exit, then it is stopped."""
    with tempfile.TemporaryFile("w+", encoding="utf-8") as errors:
        process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=errors, text=True, encoding="utf-8")
        lines: list[str] = []

        def read() -> None:
            assert process.stdout is not None
            for line in process.stdout:
                lines.append(line)

        reader = threading.Thread(target=read, daemon=True)
        reader.start()
        deadline, complete = time.monotonic() + timeout, None
        while process.poll() is None and time.monotonic() < deadline:
            if complete is None and lines and "</html>" in lines[-1]:
                complete = time.monotonic()
            if complete is not None and time.monotonic() - complete > 10:
                break
            time.sleep(0.1)
        stopped = process.poll() is None
        if stopped:
            process.kill()
        process.wait()
        reader.join(10)
        dom = "".join(lines)
        errors.seek(0)
        assert "</html>" in dom and (stopped or process.returncode == 0), (
            f"chromium failed ({process.returncode}): {errors.read()[-2000:]}"
        )
        return dom


def drive(page: Path, steps: str, profile: Path, name: str = "driven") -> dict[str, Any]:
    """Open a copy of `page` with `steps` (JavaScript using the harness's helpers, ending in `finish()`) and
    return the `out` object they filled. `profile` is Chromium's user-data folder: reuse it to keep
    localStorage between two visits."""
    text = page.read_text(encoding="utf-8")
    assert "</body>" in text
    copy = page.with_name(f"{name}.html")
    copy.write_text(text.replace("</body>", f"<script>{_HARNESS.replace('STEPS', steps)}</script></body>"), "utf-8")
    dom = _dump_dom(
        [
            chromium(),
            *_FLAGS,
            f"--user-data-dir={profile}",
            "--window-size=1500,1000",
            "--virtual-time-budget=30000",
            "--dump-dom",
            copy.as_uri(),
        ]
    )
    found = re.search(r'<pre id="measurements">(.*?)</pre>', dom, re.S)
    assert found, f"the driving script did not finish in Chromium: {dom[-1500:]}"
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
