"""The files a description or scene names: relative to it, and optionally confined to a folder.

A description given on the command line may name any file the user can read (``../x.png`` and
absolute paths included: docs/importing.md). A description that comes from elsewhere — a request
to a server — is planned with ``root``: every file it names must then resolve, symlinks followed,
inside ``root``, or planning stops with a one-line error before anything is read.
"""

from __future__ import annotations

from pathlib import Path

from lanterna.errors import LanternaInputError


def referenced(base: Path, name: str, *, source: Path, where: str,
               root: Path | None = None) -> Path:
    """The file ``name`` given at JSON path ``where`` of ``source``, relative to ``base``."""
    path = Path(base) / name
    if root is not None:
        inside = Path(root).resolve()
        if not path.resolve().is_relative_to(inside):
            raise LanternaInputError(source, f"{where}: {name!r} is outside {inside}")
    return path
