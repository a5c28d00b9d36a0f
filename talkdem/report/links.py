"""Links a published page may carry (`--viewer HREF` of the report and the leaderboard): checked as a browser
will read them, not as typed.

A browser parses an `href` with the WHATWG URL parser: it strips leading and trailing C0 control characters and
spaces, removes every tab and newline, and reads a scheme (a letter, then letters, digits, `+`, `-`, `.`, then
`:`) without regard to case. So `java<TAB>script:...`, `\\x01javascript:...` and `JavaScript:...` all run
script on click, although none starts with `javascript:`. Here a control character anywhere is refused outright
(no link needs one, and what a browser drops differs from what a person reads), and what is left is checked as
the parser reads it.

Only two kinds of link pass: a relative reference (`viewer/index.html`, `../viewer/`), which resolves
against the page wherever it is published, and an http(s) URL. An allow-list, not a list of bad schemes:
`javascript:`, `data:`, `vbscript:`, `file:` and schemes browsers add later are all out, and so is an absolute
path (one starting with `/`, `//host/` or a drive letter), which names a place on one machine or host. Percent and
entity forms (`javascript%3A...`, `javascript&#58;...`) are no scheme to the parser (`%` and `&` cannot be in
one), so they stay relative paths; the page escapes the `href`, so the browser reads exactly what was checked.
"""

from __future__ import annotations

import re
import unicodedata

__all__ = ["UnsafeLinkError", "safe_href"]

_SCHEME = re.compile(r"[A-Za-z][A-Za-z0-9+.-]*:")
_ALLOWED_SCHEMES = ("http", "https")
# Cc: C0 controls (tab, newline, ...), DEL, C1; Cf: invisible format characters (bidi overrides, zero width);
# Zl, Zp: the line and paragraph separators.
_REFUSED_CATEGORIES = ("Cc", "Cf", "Zl", "Zp")


class UnsafeLinkError(ValueError):
    """A link a published page must not carry."""


def safe_href(text: str) -> str:
    """`text` without surrounding spaces, when it is a relative reference or an http(s) URL as a browser reads
    it (see the module docstring); `UnsafeLinkError` says why not."""
    for char in text:
        if unicodedata.category(char) in _REFUSED_CATEGORIES:
            raise UnsafeLinkError(f"{text!a} holds the control character U+{ord(char):04X}; a link may hold none")
    value = text.strip()
    if not value:
        raise UnsafeLinkError("the link is empty")
    scheme = _SCHEME.match(value)
    if scheme is not None:  # also `C:\...`: a drive letter reads as a scheme
        allowed = scheme.group()[:-1].lower() in _ALLOWED_SCHEMES
    else:
        allowed = not value.startswith(("/", "\\", "~"))
    if not allowed:
        raise UnsafeLinkError(
            f"{text!a} is not a relative or http(s) link (e.g. viewer/index.html, written by `talkdem view --out`)"
        )
    return value
