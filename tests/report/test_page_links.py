"""`--viewer HREF` of the report and the leaderboard: the link is checked as a browser reads it (tabs and newlines
removed, surrounding controls stripped, the scheme without case), so no spelling of a script link gets onto a
published page; what passes resolves, in Chromium itself, to a relative or http(s) URL."""

from __future__ import annotations

import html
import json
import re
import subprocess
from pathlib import Path

import pytest
from browser_helpers import chromium
from metrics_helpers import BOOK, clean_id, reference, write_run

from talkdem.cli import main
from talkdem.leaderboard.page import render_html
from talkdem.report.html import render_report_html, viewer_link
from talkdem.report.links import UnsafeLinkError, safe_href

SCRIPT_LINKS = [
    "javascript:alert(1)",
    "JavaScript:alert(1)",
    "JAVASCRIPT:alert(1)",
    "java\tscript:alert(1)",
    "java\nscript:alert(1)",
    "java\rscript:alert(1)",
    "\x01javascript:alert(1)",
    "\x00javascript:alert(1)",
    "\x1fjavascript:alert(1)",
    " \tjavascript:alert(1)",
    "javascript:alert(1)\x7f",
    "jav\u0085ascript:alert(1)",  # a C1 control
    "\u200bjavascript:alert(1)",  # zero width space: invisible
    "\u202ejavascript:alert(1)",  # a bidi override
    "  javascript:alert(1)  ",
    "data:text/html,<script>alert(1)</script>",
    "DATA:text/html;base64,PHNjcmlwdD5hbGVydCgxKTwvc2NyaXB0Pg==",
    "vbscript:msgbox(1)",
    "VBScript:msgbox(1)",
    "file:///etc/passwd",
    "blob:https://example.org/x",
    "/home/me/viewer/index.html",
    "//evil.example/viewer",
    "\\\\evil.example\\viewer",
    "~/viewer",
    "C:\\viewer\\index.html",
    "",
    "   ",
]
"""Refused: script and data schemes however spelled, control characters anywhere, absolute paths."""

SAFE_LINKS = [
    "viewer/index.html",
    "../viewer/",
    "viewer/index.html#run=1",
    "https://huggingface.co/spaces/org/viewer",
    "HTTP://example.org/viewer",
    "javascript%3Aalert(1)",  # `%` cannot be in a scheme: a relative path
    "java%09script:alert(1)",
    "javascript&#58;alert(1)",  # an entity is not decoded: the page escapes the `&`
    "javascript&colon;alert(1)",
    "java script:alert(1)",  # a space cannot be in a scheme either
    "1javascript:alert(1)",  # nor start one
]
"""Accepted: relative references and http(s) URLs, and text that only looks like a script link."""


@pytest.mark.parametrize("href", SCRIPT_LINKS)
def test_script_and_absolute_links_are_refused(href: str) -> None:
    with pytest.raises(UnsafeLinkError):
        safe_href(href)
    with pytest.raises(UnsafeLinkError):  # also when a page is rendered from code, not the CLI
        viewer_link(href)


@pytest.mark.parametrize("href", SAFE_LINKS)
def test_relative_and_http_links_are_kept_as_written(href: str) -> None:
    assert safe_href(href) == href
    assert safe_href(f"  {href} ") == href
    assert f'href="{html.escape(href, quote=True)}"' in viewer_link(href)


def test_a_control_character_is_named_in_the_error() -> None:
    with pytest.raises(UnsafeLinkError, match=r"control character U\+0009"):
        safe_href("java\tscript:alert(1)")
    with pytest.raises(UnsafeLinkError, match=r"control character U\+000A"):
        safe_href("viewer/\nindex.html")  # refused even where the browser would resolve it harmlessly


def _fails(argv: list[str], capsys: pytest.CaptureFixture[str]) -> str:
    with pytest.raises(SystemExit) as exit_:
        main(argv)
    assert exit_.value.code == 2
    error = capsys.readouterr().err
    assert "Traceback" not in error
    return error


@pytest.mark.parametrize("command", ["report", "leaderboard"])
@pytest.mark.parametrize(
    "href", ["java\tscript:alert(1)", "\x01javascript:alert(1)", "java\nscript:alert(1)", "JavaScript:alert(1)"]
)
def test_both_commands_refuse_a_script_link_before_any_work(
    command: str, href: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    error = _fails([command, str(tmp_path / "no-such-run"), "--viewer", href, "--out", str(tmp_path / "o")], capsys)
    assert "--viewer" in error and ("control character" in error or "not a relative or http(s) link" in error)
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("command", ["report", "leaderboard"])
def test_both_commands_link_a_safe_viewer(command: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    run = write_run(tmp_path / "run", {clean_id(BOOK): reference(BOOK)})
    out = tmp_path / "out"
    argv = [command, str(run), "--viewer", " ../viewer/index.html ", "--out", str(out), "--bootstrap", "0"]
    argv += ["--no-plots"] if command == "report" else []
    assert main(argv) == 0, capsys.readouterr().err
    page = (out / ("report.html" if command == "report" else "index.html")).read_text(encoding="utf-8")
    assert '<a href="../viewer/index.html">' in page


def _resolved(hrefs: list[str], scratch: Path) -> list[str]:
    """The protocol Chromium gives each `href` on a page opened from file:// (raw hrefs, as written)."""
    anchors = "".join(f'<a href="{html.escape(h, quote=True)}">x</a>' for h in hrefs)
    script = (
        "document.getElementById('out').textContent = JSON.stringify("
        "Array.from(document.querySelectorAll('a')).map(function(a){ return a.protocol; }));"
    )
    page = scratch / "links.html"
    page.write_text(f'<!DOCTYPE html><html><body>{anchors}<pre id="out"></pre><script>{script}</script></body></html>')
    flags = ["--headless", "--no-sandbox", "--disable-gpu", "--no-first-run", "--disable-background-networking"]
    result = subprocess.run(
        [chromium(), *flags, f"--user-data-dir={scratch / 'profile'}", "--dump-dom", page.as_uri()],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    found = re.search(r'<pre id="out">(.*?)</pre>', result.stdout, re.S)
    assert found, f"chromium did not run the page: {result.stderr[-2000:]}"
    protocols: list[str] = json.loads(html.unescape(found.group(1)))
    return protocols


def test_chromium_resolves_every_accepted_link_to_file_or_http_and_the_refused_ones_to_script(tmp_path: Path) -> None:
    accepted = _resolved([safe_href(h) for h in SAFE_LINKS], tmp_path)
    assert accepted == ["file:"] * 3 + ["https:", "http:"] + ["file:"] * (len(SAFE_LINKS) - 5)
    # The same browser runs the spellings a raw comparison misses: the check above is checking what matters.
    hostile = ["java\tscript:alert(1)", "java\nscript:alert(1)", "\x01javascript:alert(1)", "JavaScript:alert(1)"]
    assert _resolved(hostile, tmp_path) == ["javascript:"] * len(hostile)


def test_pages_rendered_in_code_refuse_a_script_viewer() -> None:
    with pytest.raises(UnsafeLinkError):
        render_report_html([], [], [], viewer="java\tscript:alert(1)")
    with pytest.raises(UnsafeLinkError):
        render_html([], viewer="\x01javascript:alert(1)")
