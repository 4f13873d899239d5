"""Reading input files and writing output files with one-line errors; writes are atomic."""

from __future__ import annotations

import json
import os
import tempfile
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from lanterna.errors import LanternaInputError


def read_input(src: Path, what: str) -> bytes:
    """Return the bytes of ``src``; ``what`` names the expected kind ("a PTM file", "an image")."""
    try:
        return src.read_bytes()
    except FileNotFoundError:
        raise LanternaInputError(src, "file not found") from None
    except IsADirectoryError:
        raise LanternaInputError(src, f"is a directory, not {what}") from None
    except OSError as exc:
        raise LanternaInputError(src, f"cannot read file ({exc.strerror})") from None


def write_atomic(dest: Path, chunks: Sequence[bytes]) -> None:
    """Write ``chunks`` to a temporary file beside ``dest``, then rename it into place."""
    try:
        fd, tmp = tempfile.mkstemp(dir=dest.parent, prefix=f".{dest.name}.", suffix=".tmp")
    except OSError as exc:
        raise LanternaInputError(dest, f"cannot write file ({exc.strerror})") from None
    try:
        with os.fdopen(fd, "wb") as out:
            for chunk in chunks:
                out.write(chunk)
        os.replace(tmp, dest)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def read_json(path: Path) -> dict[str, Any]:
    """Read a JSON object with one-line errors."""
    try:
        doc = json.loads(Path(path).read_text())
    except OSError as err:
        raise LanternaInputError(path, f"cannot read ({err.strerror})") from None
    except ValueError as err:
        raise LanternaInputError(path, f"not valid JSON ({err})") from None
    if not isinstance(doc, dict):
        raise LanternaInputError(path, "expected a JSON object")
    return doc
