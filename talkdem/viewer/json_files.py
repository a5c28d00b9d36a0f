"""Reading the small JSON files people hand the viewer and the report (an error sample, a labels file): every
way such a file can be unreadable is one error naming the file, and the line where the text tells it.

Python's parser takes `NaN` and `Infinity`, which JSON does not have and the viewer's data cannot carry; they
are refused here, where the file is read, not later where the page is written.
"""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

__all__ = ["MAX_JSON_BYTES", "read_json_file"]

MAX_JSON_BYTES = 64 * 1024 * 1024
"""The largest sample or labels file read (one of 10,000 labels is about 2 MB)."""

# A string (skipped whole, so a quoted "NaN" is text) or a constant JSON does not have.
_CONSTANT = re.compile(r'"(?:\\.|[^"\\])*"|(-?Infinity|NaN)')


class _NotJsonNumber(Exception):
    pass


def _refuse_constant(name: str) -> Any:
    raise _NotJsonNumber(name)


def read_json_file(path: Path, what: str) -> Any:
    """The JSON value of `path` (`what` names the kind of file in errors: "an error sample", "a labels file")."""
    if path.is_file() and path.stat().st_size > MAX_JSON_BYTES:
        raise ValueError(f"{path}: larger than {MAX_JSON_BYTES // (1024 * 1024)} MiB; not {what}")
    data = path.read_bytes()
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        number = data.count(b"\n", 0, exc.start) + 1
        raise ValueError(f"{path}, line {number}: not UTF-8 text (expected {what} written as JSON)") from None
    try:
        return json.loads(text, parse_constant=_refuse_constant)
    except json.JSONDecodeError as exc:
        raise ValueError(f"{path}: not JSON ({exc.msg}, line {exc.lineno} column {exc.colno})") from None
    except RecursionError:
        raise ValueError(f"{path}: JSON nested too deeply to read") from None
    except _NotJsonNumber as exc:
        found = next((m for m in _CONSTANT.finditer(text) if m.group(1)), None)
        where = f", line {text.count(chr(10), 0, found.start()) + 1}" if found else ""
        raise ValueError(f"{path}{where}: holds {exc}, which is not a JSON number") from None
    except ValueError:  # an integer longer than Python converts (4,300 digits)
        raise ValueError(f"{path}: not JSON (a number too long to read)") from None
