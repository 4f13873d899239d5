"""Output failures as one-line errors naming the output, and JSON with finite numbers only.

A full disk, a read-only or foreign folder, or libvips failing to write a tile is the
:class:`~lanterna.errors.LanternaInputError` ``OUT: cannot write (No space left on device);
nothing was changed``, raised by :func:`write_errors` around the writer's own file operations
(never around reading the sources, whose errors name the source). :func:`json_text` refuses
``NaN`` and infinities, which ``json.dumps`` would write as ``NaN``/``Infinity`` (not JSON: the
viewer's ``JSON.parse`` rejects the document), naming the file and the first such value.
"""

from __future__ import annotations

import json
import re
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import pyvips

from lanterna.errors import LanternaInputError
from lanterna.tiler.documents import non_finite

_SYSTEM_ERROR = re.compile(r"system error: (.+)")
#: An indented JSON array of numbers only (a PCA basis, a light list, scales and biases); the
#: newline after ``[`` cannot occur inside a JSON string (``json.dumps`` escapes it).
_NUMBER_ARRAY = re.compile(r"\[\n\s*-?[0-9][-+.eE0-9]*(?:\s*,\s*-?[0-9][-+.eE0-9]*)*\s*\]")


def write_error(out: Path, err: OSError | pyvips.Error) -> LanternaInputError:
    """Return the one-line error for failing to write the output ``out``."""
    return LanternaInputError(out, f"cannot write ({failure_reason(err)}); nothing was changed")


def failure_reason(err: OSError | pyvips.Error) -> str:
    """Say in a few words why a write failed: the OS's reason, or libvips's first one."""
    if isinstance(err, OSError):
        return err.strerror or str(err) or type(err).__name__
    lines = [line.strip() for line in str(err).splitlines() if line.strip()]
    for line in lines:  # libvips passes the OS's reason on as "system error: …"
        m = _SYSTEM_ERROR.match(line)
        if m and not m.group(1).startswith("Unknown error"):
            return m.group(1)
    detail = lines[1] if len(lines) > 1 else (lines[0] if lines else "libvips failed")
    return detail[:200]


@contextmanager
def write_errors(out: Path) -> Iterator[None]:
    """Turn an ``OSError`` or ``pyvips.Error`` raised inside into :func:`write_error`."""
    try:
        yield
    except (OSError, pyvips.Error) as err:
        raise write_error(out, err) from None


def _one_line(match: re.Match[str]) -> str:
    return re.sub(r"\s+", "", match.group(0)).replace(",", ", ")


def json_text(doc: Any, path: Path) -> str:
    """Return ``doc`` as indented JSON, or raise naming ``path`` if a number is not finite.

    Arrays of numbers are written on one line: a PCA basis of thousands of bytes (a layer's
    ``basis``) would otherwise take one line per number and several times the bytes.
    """
    try:
        return _NUMBER_ARRAY.sub(_one_line, json.dumps(doc, indent=2, allow_nan=False))
    except ValueError:
        found = non_finite(doc)
        if found is None:
            raise
        where = "the document" if found[0] == "(document)" else found[0]
        raise LanternaInputError(path, f"cannot write: {where} is {found[1]} (JSON has no NaN "
                                 "or infinity)") from None
