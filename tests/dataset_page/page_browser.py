"""Open a sample page in headless Chromium with a script that records every error and console error from the
first line on, runs a test's STEPS after load (they change filters as a reader does) and writes what it saw
into the DOM that `--dump-dom` prints."""

from __future__ import annotations

import html
import json
import re
from pathlib import Path
from typing import Any

from browser_helpers import chromium
from viewer_browser import _FLAGS, _dump_dom

_FIRST = """<script>
window.__errors = [];
window.addEventListener('error', function(e){ window.__errors.push(String(e.message)); });
var __consoleError = console.error;
console.error = function(){ window.__errors.push(Array.prototype.join.call(arguments, ' '));
  return __consoleError.apply(console, arguments); };
</script>"""

_LAST = """<script>
window.addEventListener('load', function(){
  var out = {};
  var $ = function(id){ return document.getElementById(id); };
  function set(id, value){ var e = $(id); e.value = value;
    e.dispatchEvent(new Event(e.tagName === 'INPUT' ? 'input' : 'change', {bubbles: true})); }
  function visible(selector){ return Array.prototype.filter.call(document.querySelectorAll(selector),
    function(e){ return e.offsetParent !== null; }); }
  function finish(){ out.errors = window.__errors; var pre = document.createElement('pre');
    pre.id = 'measurements'; pre.textContent = JSON.stringify(out); document.body.appendChild(pre); }
  try {
STEPS
  } catch (e) { out.error = String(e); }
  finish();
});
</script>"""


def drive(page: Path, steps: str, scratch: Path) -> dict[str, Any]:
    """Run `steps` (JavaScript using `$`, `set`, `visible` and filling `out`) on a copy of `page`."""
    text = page.read_text(encoding="utf-8")
    assert "<head>" in text and "</body>" in text
    copy = scratch / f"driven-{page.name}"
    copy.write_text(
        text.replace("<head>", "<head>" + _FIRST, 1).replace("</body>", _LAST.replace("STEPS", steps) + "</body>"),
        encoding="utf-8",
    )
    # The viewer's runner: it stops a headless Chromium that printed the DOM but does not exit (a busy machine).
    dom = _dump_dom(
        [
            chromium(),
            *_FLAGS,
            f"--user-data-dir={scratch / 'profile'}",
            "--window-size=1500,1000",
            "--virtual-time-budget=10000",
            "--dump-dom",
            copy.as_uri(),
        ]
    )
    found = re.search(r'<pre id="measurements">(.*?)</pre>', dom, re.S)
    assert found, f"the driving script did not run in Chromium: {dom[-1500:]}"
    data: dict[str, Any] = json.loads(html.unescape(found.group(1)))
    assert "error" not in data, data["error"]
    return data
