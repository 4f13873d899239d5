"""Reading input files and writing output files with one-line errors; writes are atomic."""

from __future__ import annotations

import json
import os
import stat
import tempfile
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from lanterna.errors import LanternaInputError


def read_input(src: Path, what: str, *, max_bytes: int | None = None) -> bytes:
    """Return the bytes of the regular file ``src``; ``what`` names the expected kind ("a PTM
    file", "an image").

    Only regular files are read: a device (``/dev/zero``), a FIFO or a socket is refused before
    any byte is read (the file is opened non-blocking, so a FIFO cannot block), and so is a file
    over ``max_bytes``.
    """
    src = Path(src)
    try:
        fd = os.open(src, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    except FileNotFoundError:
        raise LanternaInputError(src, "file not found") from None
    except IsADirectoryError:
        raise LanternaInputError(src, f"is a directory, not {what}") from None
    except OSError as exc:
        raise LanternaInputError(src, f"cannot read file ({exc.strerror})") from None
    info = os.fstat(fd)
    if not stat.S_ISREG(info.st_mode) or (max_bytes is not None and info.st_size > max_bytes):
        os.close(fd)
        if stat.S_ISDIR(info.st_mode):
            raise LanternaInputError(src, f"is a directory, not {what}")
        if not stat.S_ISREG(info.st_mode):
            raise LanternaInputError(src, f"is not a regular file (a device, FIFO or socket), not "
                                     f"{what}")
        raise LanternaInputError(src, f"is {info.st_size:,} bytes; at most {max_bytes:,} are "
                                 f"read as {what}")
    with os.fdopen(fd, "rb") as f:
        try:
            return f.read()
        except OSError as exc:
            raise LanternaInputError(src, f"cannot read file ({exc.strerror})") from None


def check_regular_file(src: Path, what: str) -> Path:
    """Return ``src`` if it is a regular file (symlinks followed), else raise a one-line error.

    For readers that hand a file name to a decoder (libvips) rather than reading it here.
    """
    src = Path(src)
    try:
        mode = os.stat(src).st_mode
    except FileNotFoundError:
        raise LanternaInputError(src, "file not found") from None
    except OSError as exc:
        raise LanternaInputError(src, f"cannot read file ({exc.strerror})") from None
    if stat.S_ISDIR(mode):
        raise LanternaInputError(src, f"is a directory, not {what}")
    if not stat.S_ISREG(mode):
        raise LanternaInputError(src, f"is not a regular file (a device, FIFO or socket), not "
                                 f"{what}")
    return src


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
