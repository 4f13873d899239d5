"""A bare WSGI app serving tile files (bench only): the floor of a Python server's cost per tile.

No routing framework, no containment checks, no conditional requests: it opens the file under
``$FLOOR_ROOT`` named by the path after ``/datasets/`` and hands it to the server's
``wsgi.file_wrapper`` (sendfile under gunicorn). Not safe for any real use; it exists so the load
test can show how much of gunicorn's cost per tile is the Flask app and how much is Python HTTP
serving itself.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable
from typing import Any

ROOT = os.environ.get("FLOOR_ROOT", "/nonexistent")


def app(environ: dict[str, Any], start_response: Callable[..., Any]) -> Iterable[bytes]:
    """Serve ``/datasets/<path>`` from ``$FLOOR_ROOT/<path>`` as image/jpeg."""
    path = environ["PATH_INFO"].removeprefix("/datasets/")
    try:
        f = open(os.path.join(ROOT, path), "rb")  # closed by the file wrapper
    except OSError:
        start_response("404 Not Found", [("Content-Length", "0")])
        return [b""]
    size = os.fstat(f.fileno()).st_size
    start_response("200 OK", [("Content-Type", "image/jpeg"), ("Content-Length", str(size)),
                              ("Access-Control-Allow-Origin", "*")])
    wrapper: Iterable[bytes] = environ["wsgi.file_wrapper"](f, 65536)
    return wrapper
