"""Render a page in headless Chromium (Debian's `chromium`, installed by `make setup-test`) and read back
what a reader sees: a script added to a copy of the page measures the laid-out DOM after load and writes
the measurements into the DOM that `--dump-dom` prints."""

from __future__ import annotations

import json
import re
import shutil
import subprocess
from pathlib import Path
from typing import Any

_FLAGS = (
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--hide-scrollbars",
)

_MEASURE = """
window.addEventListener('load', function(){
  function box(e){var r = e.getBoundingClientRect(); return {x: r.x, y: r.y, w: r.width, h: r.height};}
  var out = {tables: [], images: [], blocks: [], width: document.documentElement.scrollWidth,
             viewport: window.innerWidth};
  document.querySelectorAll('table').forEach(function(t){
    var rows = [];
    t.querySelectorAll('tbody tr').forEach(function(tr){
      rows.push(Array.from(tr.cells).map(function(td){var b = box(td);
        b.text = td.innerText.trim(); b.align = getComputedStyle(td).textAlign; b.cls = td.className;
        b.scrollW = td.scrollWidth; b.clientW = td.clientWidth; return b;}));
    });
    var head = Array.from(t.querySelectorAll('thead th')).map(function(th){return th.innerText.trim();});
    out.tables.push({id: t.id, cls: t.className, section: (t.closest('section') || {}).id || '', head: head,
                     rows: rows, box: box(t)});
  });
  document.querySelectorAll('img').forEach(function(i){var b = box(i);
    b.alt = i.alt; b.naturalW = i.naturalWidth; b.naturalH = i.naturalHeight; b.complete = i.complete;
    out.images.push(b);});
  document.querySelectorAll('body > *:not(script), section > *, figure > *').forEach(function(e){
    if (e.id === 'measurements') return; var b = box(e); b.tag = e.tagName; b.id = e.id; out.blocks.push(b);});
  var pre = document.createElement('pre'); pre.id = 'measurements'; pre.textContent = JSON.stringify(out);
  document.body.appendChild(pre);
});
"""


def chromium() -> str:
    """The Chromium binary; a missing browser is a failure with the fix, never a skip."""
    found = shutil.which("chromium") or shutil.which("chromium-browser")
    if found is None:
        raise AssertionError(
            "Chromium is missing: the browser tests need Debian's `chromium` "
            "(`make setup-test` installs it: apt-get install -y chromium)"
        )
    return found


def _run(args: list[str], profile: Path) -> str:
    result = subprocess.run(
        [chromium(), *_FLAGS, f"--user-data-dir={profile}", *args],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert result.returncode == 0, f"chromium failed ({result.returncode}): {result.stderr[-2000:]}"
    return result.stdout


def measure(page: Path, scratch: Path) -> dict[str, Any]:
    """Lay `page` out at 1500 px wide (the report's maximum width) and return the measurements (tables,
    images, blocks, the page's scroll width and the viewport's width)."""
    scratch.mkdir(parents=True, exist_ok=True)
    copy = scratch / f"measured-{page.name}"
    text = page.read_text(encoding="utf-8")
    assert "</body>" in text
    copy.write_text(text.replace("</body>", f"<script>{_MEASURE}</script></body>"), encoding="utf-8")
    dom = _run(
        ["--window-size=1500,1000", "--virtual-time-budget=10000", "--dump-dom", copy.as_uri()],
        scratch / "profile-dom",
    )
    found = re.search(r'<pre id="measurements">(.*?)</pre>', dom, re.S)
    assert found, "the measuring script did not run in Chromium"
    import html

    data: dict[str, Any] = json.loads(html.unescape(found.group(1)))
    return data


def screenshot(page: Path, out: Path, scratch: Path, size: str = "1400,1600") -> Path:
    """A PNG of `page` as Chromium draws it."""
    _run([f"--window-size={size}", f"--screenshot={out}", page.as_uri()], scratch / "profile-shot")
    assert out.is_file(), f"chromium wrote no screenshot to {out}"
    return out


def overlaps(a: dict[str, float], b: dict[str, float], slack: float = 0.5) -> bool:
    """Whether two boxes share area (touching edges do not count)."""
    return (
        a["x"] + slack < b["x"] + b["w"]
        and b["x"] + slack < a["x"] + a["w"]
        and a["y"] + slack < b["y"] + b["h"]
        and b["y"] + slack < a["y"] + a["h"]
    )


def distinct_colors(png: Path) -> int:
    """How many distinct colors a screenshot holds (a blank page has one)."""
    import matplotlib.image as mpimg
    import numpy as np

    pixels = mpimg.imread(png)
    flat = (pixels[..., :3] * 255).astype("uint8").reshape(-1, 3)
    return len(np.unique(flat, axis=0))
