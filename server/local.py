"""The built-in server of ``lanterna serve`` (without ``--workers``), on a socket bound first.

:func:`listen` binds and listens before anything is printed, so a busy port is reported before
any URL (the same socket is handed to gunicorn with ``--workers``, :func:`lanterna.server.wsgi.
run_gunicorn`). :func:`run_threaded` serves the app on it with Werkzeug's threaded server, a thread
per connection: right for the few connections of one browser on this machine. Werkzeug's own
start-up banner is not printed, and requests are logged one line each only when asked (a viewer
fetches thousands of tiles); 5xx responses are always logged, with the app's traceback.

Every response is closed, even when the browser drops the connection: Werkzeug's handler closes
the app's response (an open tile file, for a tile) only after draining the request socket, and a
connection the browser reset (it cancels tile requests as it zooms) makes that drain raise, which
left the file to the garbage collector. :class:`_ClosingHandler` closes it after every request.
The tests' live server (``tests/python/fixtures/servers.py``) runs this same server.
"""

from __future__ import annotations

import socket
from collections.abc import Iterable, Iterator
from typing import TYPE_CHECKING, Any

from flask import Flask
from werkzeug.serving import BaseWSGIServer, WSGIRequestHandler, make_server

if TYPE_CHECKING:
    from _typeshed.wsgi import StartResponse, WSGIApplication, WSGIEnvironment

#: Connections the kernel queues before the server accepts them (gunicorn's default too).
BACKLOG = 2048


def listen(host: str, port: int) -> socket.socket:
    """Return a TCP socket bound to ``host:port`` and listening; port 0 picks a free port.

    Raises :class:`OSError` (``errno.EADDRINUSE`` for a busy port, :class:`socket.gaierror`
    for an unknown host name).
    """
    family, _, _, _, address = socket.getaddrinfo(host, port, type=socket.SOCK_STREAM,
                                                  flags=socket.AI_PASSIVE)[0]
    return socket.create_server(address, family=family, backlog=BACKLOG)


#: The environ key under which :func:`_remember_response` keeps the app's response.
_RESPONSE = "lanterna.response"


class _Response:
    """An app's response, iterated as it is and closed at most once."""

    def __init__(self, body: Iterable[bytes]) -> None:
        self._body: Iterable[bytes] | None = body

    def __iter__(self) -> Iterator[bytes]:
        return iter(self._body or ())

    def close(self) -> None:
        body, self._body = self._body, None
        close = getattr(body, "close", None)
        if close is not None:
            close()


def _remember_response(app: WSGIApplication) -> WSGIApplication:
    """Wrap ``app`` so that its response is kept in the environ, for the handler to close."""

    def wrapped(environ: WSGIEnvironment, start_response: StartResponse) -> Iterable[bytes]:
        response = environ[_RESPONSE] = _Response(app(environ, start_response))
        return response

    return wrapped


class _ClosingHandler(WSGIRequestHandler):
    """Werkzeug's request handler, closing the app's response after every request (Werkzeug
    keeps the request's environ as ``self.environ``)."""

    def run_wsgi(self) -> None:
        try:
            super().run_wsgi()
        finally:
            environ: dict[str, Any] | None = getattr(self, "environ", None)
            response = environ.pop(_RESPONSE, None) if environ is not None else None
            if response is not None:
                response.close()


class _ErrorsOnlyHandler(_ClosingHandler):
    """:class:`_ClosingHandler`, logging only the requests answered with a 5xx status."""

    def log_request(self, code: int | str = "-", size: int | str = "-") -> None:
        if str(code).startswith("5"):
            super().log_request(code, size)


def threaded_server(app: Flask, listener: socket.socket, *,
                    access_log: bool = False) -> BaseWSGIServer:
    """Return Werkzeug's threaded server for ``app`` on ``listener`` (closed: the server holds
    its own duplicate), logging every request only with ``access_log``."""
    host, port = listener.getsockname()[:2]
    handler = _ClosingHandler if access_log else _ErrorsOnlyHandler
    server = make_server(str(host), int(port), _remember_response(app), threaded=True,
                         request_handler=handler, fd=listener.fileno())
    listener.close()
    return server


def run_threaded(app: Flask, listener: socket.socket, *, access_log: bool = False) -> None:
    """Serve ``app`` on ``listener`` until Ctrl-C; log every request only with ``access_log``."""
    threaded_server(app, listener, access_log=access_log).serve_forever()
