"""The authoring token: who may change a dataset through the API (docs/serving.md).

One shared secret, given to ``lanterna serve`` in a file (``--authoring-token-file FILE``: its
first line) or in the environment (:data:`TOKEN_ENV`), never on the command line, where other
users of the machine could read it in the process list. Requests that write send it as
``Authorization: Bearer TOKEN``; it is compared in constant time (:func:`hmac.compare_digest`).
Without a token the API is read-only.
"""

from __future__ import annotations

import hmac
import os
import stat
from collections.abc import Mapping
from pathlib import Path

from lanterna.errors import LanternaInputError

#: The environment variable holding the token when no file is given.
TOKEN_ENV = "LANTERNA_AUTHORING_TOKEN"
#: The shortest token accepted.
MIN_TOKEN_LENGTH = 16
_MAX_FILE_BYTES = 4096


def read_token_file(path: Path) -> str:
    """The token in the first line of the regular file ``path`` (one-line errors)."""
    path = Path(path)
    try:
        if not stat.S_ISREG(os.stat(path).st_mode):
            raise LanternaInputError(path, "the authoring token file must be a regular file")
        with open(path, "rb") as f:
            data = f.read(_MAX_FILE_BYTES)
    except OSError as err:
        raise LanternaInputError(path, f"cannot read the authoring token file "
                                 f"({err.strerror or err})") from None
    lines = data.decode("utf-8", "replace").splitlines()
    return check_token(lines[0].strip() if lines else "", str(path))


def check_token(token: str, where: str) -> str:
    """Return ``token`` if it is long enough and printable, else raise naming ``where``."""
    if len(token) < MIN_TOKEN_LENGTH:
        raise LanternaInputError(where, f"the authoring token must be at least "
                                 f"{MIN_TOKEN_LENGTH} characters (got {len(token)})")
    if not token.isprintable() or not token.isascii():
        raise LanternaInputError(where, "the authoring token must be printable ASCII")
    return token


def authoring_token(token_file: Path | None, environ: Mapping[str, str]) -> str | None:
    """The token from ``token_file`` if given, else from :data:`TOKEN_ENV`, else None."""
    if token_file is not None:
        return read_token_file(token_file)
    value = environ.get(TOKEN_ENV, "").strip()
    return check_token(value, TOKEN_ENV) if value else None


def bearer_matches(header: str | None, token: str) -> bool:
    """Whether an ``Authorization`` header carries ``Bearer`` ``token`` (constant time)."""
    scheme, _, given = (header or "").strip().partition(" ")
    if scheme.lower() != "bearer":
        return False
    return hmac.compare_digest(given.strip().encode("utf-8", "replace"), token.encode("utf-8"))
