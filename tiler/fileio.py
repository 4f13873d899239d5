"""Reading input files with one-line errors: regular files only, of bounded size."""

from __future__ import annotations

import os
import stat
from pathlib import Path

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
    try:
        _check_mode(src, info.st_mode, what)
        if max_bytes is not None and info.st_size > max_bytes:
            raise LanternaInputError(src, f"is {info.st_size:,} bytes; at most {max_bytes:,} are "
                                     f"read as {what}")
    except LanternaInputError:
        os.close(fd)
        raise
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
    _check_mode(src, mode, what)
    return src


def _check_mode(src: Path, mode: int, what: str) -> None:
    """Refuse anything but a regular file: a directory, a device, a FIFO, a socket."""
    if stat.S_ISDIR(mode):
        raise LanternaInputError(src, f"is a directory, not {what}")
    if not stat.S_ISREG(mode):
        raise LanternaInputError(src, f"is not a regular file (a device, FIFO or socket), not "
                                 f"{what}")
