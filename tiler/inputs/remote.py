"""Read a remote source over HTTP(S) with one-line errors: bounded size, bounded waits.

:func:`fetch` returns a response's bytes, refusing before reading when ``Content-Length`` is
over the bound and stopping one byte past it otherwise; each connection and read waits at most
:data:`TIMEOUT_S`. Only ``http://`` and ``https://`` URLs are fetched, redirects included (a
redirect elsewhere, which urllib would follow to ``ftp://``, is an error instead).
"""

from __future__ import annotations

import http.client
import urllib.error
import urllib.request
from typing import Any

from lanterna.errors import LanternaInputError

#: Seconds each connection attempt and each read may wait.
TIMEOUT_S = 30.0
USER_AGENT = "lanterna-import"


class _HttpOnly(urllib.request.HTTPRedirectHandler):
    """Follow redirects to http(s) URLs only (None: urllib raises the 3xx as an HTTPError)."""

    def redirect_request(self, req: urllib.request.Request, fp: Any, code: int, msg: str,
                         headers: Any, newurl: str) -> urllib.request.Request | None:
        if not is_url(newurl):
            return None
        return super().redirect_request(req, fp, code, msg, headers, newurl)


_OPENER = urllib.request.build_opener(_HttpOnly)


def is_url(text: object) -> bool:
    """True when ``text`` is an ``http://`` or ``https://`` URL."""
    return str(text).lower().startswith(("http://", "https://"))


def fetch(url: str, what: str, *, max_bytes: int, accept: str = "*/*",
          timeout: float = TIMEOUT_S) -> bytes:
    """Return the body of ``GET url``; ``what`` names the expected kind ("a manifest").

    Raises
    ------
    LanternaInputError
        Not an http(s) URL, an HTTP error status (a redirect elsewhere than http(s) is its 3xx),
        no connection, no answer within ``timeout``, or a body over ``max_bytes``.
    """
    if not is_url(url):
        raise LanternaInputError(url, f"expected an http:// or https:// URL of {what}")
    request = urllib.request.Request(url, headers={"Accept": accept, "User-Agent": USER_AGENT})
    try:
        with _OPENER.open(request, timeout=timeout) as response:
            length = response.headers.get("Content-Length", "")
            if length.isdigit() and int(length) > max_bytes:
                raise LanternaInputError(url, f"is {int(length):,} bytes; at most {max_bytes:,} "
                                         f"are read as {what}")
            data: bytes = response.read(max_bytes + 1)
    except urllib.error.HTTPError as exc:
        raise LanternaInputError(url, f"HTTP {exc.code} {exc.reason} (expected {what})") from None
    except urllib.error.URLError as exc:
        reason = exc.reason if isinstance(exc.reason, str) else getattr(
            exc.reason, "strerror", None) or exc.reason
        raise LanternaInputError(url, f"cannot fetch {what} ({reason})") from None
    except TimeoutError:
        raise LanternaInputError(url, f"no answer within {timeout:g} s (expected {what})") \
            from None
    except (OSError, http.client.HTTPException, ValueError) as exc:
        raise LanternaInputError(url, f"cannot fetch {what} ({type(exc).__name__})") from None
    if len(data) > max_bytes:
        raise LanternaInputError(url, f"is over {max_bytes:,} bytes; at most that is read as "
                                 f"{what}")
    return data
