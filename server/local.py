"""The built-in server of ``lanterna serve`` (without ``--workers``), on a socket bound first.

:func:`listen` binds and listens before anything is printed, so a busy port is reported before
any URL (the same socket is handed to gunicorn with ``--workers``, :func:`lanterna.server.wsgi.
run_gunicorn`). :func:`run_threaded` serves the app on it with Werkzeug's threaded server, a thread
per connection: right for the few connections of one browser on this machine. Werkzeug's own
start-up banner is not printed, and requests are logged one line each only when asked (a viewer
fetches thousands of tiles); 5xx responses are always logged, with the app's traceback.
"""

from __future__ import annotations

import socket

from flask import Flask
from werkzeug.serving import WSGIRequestHandler, make_server

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


class _ErrorsOnlyHandler(WSGIRequestHandler):
    """Werkzeug's request handler, logging only the requests answered with a 5xx status."""

    def log_request(self, code: int | str = "-", size: int | str = "-") -> None:
        if str(code).startswith("5"):
            super().log_request(code, size)


def run_threaded(app: Flask, listener: socket.socket, *, access_log: bool = False) -> None:
    """Serve ``app`` on ``listener`` until Ctrl-C; log every request only with ``access_log``."""
    host = str(listener.getsockname()[0])
    handler: type[WSGIRequestHandler] = WSGIRequestHandler if access_log else _ErrorsOnlyHandler
    server = make_server(host, listener.getsockname()[1], app, threaded=True,
                         request_handler=handler, fd=listener.fileno())
    listener.close()  # the server holds its own duplicate of the socket
    server.serve_forever()
