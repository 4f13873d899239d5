"""Error responses: short plain text, never HTML pages or stack traces.

:func:`register_error_handlers` makes every HTTP error (404, 405, …) a one-line ``text/plain``
body, and turns any unexpected exception into a logged ``500 Internal Server Error`` whose body
says only that. Redirects raised by routing (3xx) pass through untouched.
"""

from __future__ import annotations

from http import HTTPStatus

from flask import Flask, Response
from werkzeug.exceptions import HTTPException


def plain_error(status: int, message: str) -> Response:
    """Return a ``text/plain`` error response: the status line, and a reason if given."""
    try:
        phrase = HTTPStatus(status).phrase
    except ValueError:
        phrase = "Error"
    body = f"{status} {phrase}" + (f": {message}" if message else "") + "\n"
    return Response(body, status=status, mimetype="text/plain")


def register_error_handlers(app: Flask) -> None:
    """Register the plain-text handlers for HTTP errors and unexpected exceptions on ``app``."""

    @app.errorhandler(HTTPException)
    def http_error(err: HTTPException) -> Response | HTTPException:
        if err.code is None or err.code < 400:
            return err
        resp = plain_error(err.code, "")
        for name, value in err.get_headers():
            if name.lower() not in ("content-type", "content-length"):
                resp.headers[name] = value
        return resp

    @app.errorhandler(Exception)
    def unexpected(err: Exception) -> Response | HTTPException:
        if isinstance(err, HTTPException):
            return http_error(err)
        app.logger.exception("unhandled error")
        return plain_error(500, "")
