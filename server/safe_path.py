"""Map request paths to files strictly inside the data root.

Every file the server reads goes through :func:`contained_file`: the relative path is checked
segment by segment (no ``..``, ``.``, empty or hidden segments, backslashes, NUL bytes or
absolute paths), then resolved with symlinks followed and checked to lie inside the resolved
root. ``werkzeug.security.safe_join`` alone does not follow symlinks, so a link inside the root
pointing outside it would escape; here it does not. :func:`raw_path_is_safe` refuses request
URIs whose encoded form hides a slash (``%2F``) or a NUL (``%00``) that routing would otherwise
see decoded. Backslashes are not separators on POSIX; every route refuses them in its own terms
(404 for a path, 400 for a IIIF parameter, as the validator expects).
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from pathlib import Path
from typing import Any

_SEGMENT = re.compile(r"^[A-Za-z0-9_,:!^.=+~-]+$")
_ENCODED_BAD = re.compile(r"%(2f|00)", re.IGNORECASE)


def safe_relative(relative: str) -> bool:
    """Return whether ``relative`` is a plain relative path of ordinary segments.

    Segments may use letters, digits and ``_ , : ! ^ . = + ~ -`` (what dataset files and IIIF
    parameters use), must not start with a dot (no ``.``/``..``, no hidden files) and must not
    be empty (no ``//`` and no leading ``/``).
    """
    if not relative or len(relative) > 1024:
        return False
    return all(_SEGMENT.match(seg) and not seg.startswith(".")
               for seg in relative.split("/"))


def contained_file(root: Path, relative: str) -> Path | None:
    """Return the resolved file ``root/relative`` if it exists inside ``root``, else ``None``.

    Parameters
    ----------
    root:
        The data root, already resolved (``Path.resolve()``).
    relative:
        A ``/``-separated path from the request.

    Returns
    -------
    The resolved path of an existing regular file inside ``root``, or ``None`` for anything
    else: a bad path, a missing file, a folder, or a symlink leading outside the root.
    """
    if not safe_relative(relative):
        return None
    try:
        target = (root / relative).resolve(strict=True)
    except (OSError, RuntimeError):  # missing, or a symlink loop
        return None
    if not target.is_relative_to(root) or not target.is_file():
        return None
    return target


def contained_dir(root: Path, relative: str) -> Path | None:
    """Return the resolved folder ``root/relative`` if it exists inside ``root``, else ``None``."""
    if not safe_relative(relative):
        return None
    try:
        target = (root / relative).resolve(strict=True)
    except (OSError, RuntimeError):
        return None
    if not target.is_relative_to(root) or not target.is_dir():
        return None
    return target


def raw_path_is_safe(environ: Mapping[str, Any]) -> bool:
    """Return whether the request's raw URI path has no encoded ``/`` and no NUL.

    Uses ``RAW_URI``/``REQUEST_URI`` (set by werkzeug's server and gunicorn) for ``%2F``; the
    decoded ``PATH_INFO`` is checked for NUL.
    """
    raw = str(environ.get("RAW_URI") or environ.get("REQUEST_URI") or "")
    path = raw.split("?", 1)[0]
    decoded = str(environ.get("PATH_INFO", ""))
    return not _ENCODED_BAD.search(path) and "\x00" not in decoded
