"""The built-in server of ``lanterna serve`` (:mod:`lanterna.server.local`)."""

from __future__ import annotations

import socket
import struct
import threading
import time
from collections.abc import Iterator

import pytest
from flask import Flask, Response

from lanterna.server.local import listen, threaded_server

#: How long the server's threads get to finish the dropped requests (not a performance bound).
DEADLINE_S = 30


class _Body:
    """A response body that records whether the server closed it, as a tile file is closed."""

    def __init__(self, size: int, closed: list[int]) -> None:
        self._chunks = [b"x" * 8192] * (size // 8192) + [b"x" * (size % 8192)]
        self._closed = closed

    def __iter__(self) -> Iterator[bytes]:
        return iter(self._chunks)

    def close(self) -> None:
        self._closed.append(1)


def _reset_after_first_bytes(port: int) -> None:
    """Ask for ``/body``, read the first bytes of the answer, then reset the connection (RST, as
    a browser cancelling a tile request does)."""
    with socket.create_connection(("127.0.0.1", port)) as conn:
        conn.sendall(b"GET /body HTTP/1.1\r\nHost: localhost\r\n\r\n")
        assert conn.recv(64).startswith(b"HTTP/1.1 200")
        conn.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))


@pytest.mark.parametrize("size", [300, 4_000_000], ids=["sent-whole", "cut-short"])
def test_a_response_is_closed_when_the_browser_resets_the_connection(size: int) -> None:
    # sent-whole: the body is written before the reset, and Werkzeug's drain of the request
    # socket then fails; cut-short: the write itself fails. Either way the body is closed.
    closed: list[int] = []
    app = Flask(__name__)
    app.add_url_rule("/body", "body", lambda: Response(_Body(size, closed)))
    server = threaded_server(app, listen("127.0.0.1", 0))
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        requests = 20
        for _ in range(requests):
            _reset_after_first_bytes(server.port)
        deadline = time.monotonic() + DEADLINE_S
        while len(closed) < requests and time.monotonic() < deadline:
            time.sleep(0.05)
        assert len(closed) == requests
    finally:
        server.shutdown()
        server.server_close()
        thread.join(5)


def test_a_response_is_closed_once_after_a_normal_request() -> None:
    closed: list[int] = []
    app = Flask(__name__)
    app.add_url_rule("/body", "body", lambda: Response(_Body(300, closed)))
    server = threaded_server(app, listen("127.0.0.1", 0))
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        with socket.create_connection(("127.0.0.1", server.port)) as conn:
            conn.sendall(b"GET /body HTTP/1.1\r\nHost: localhost\r\nConnection: close\r\n\r\n")
            answer = b""
            while chunk := conn.recv(65536):
                answer += chunk
        assert answer.startswith(b"HTTP/1.1 200")
        assert answer.endswith(b"x" * 300 + b"\r\n0\r\n\r\n")  # the last chunk, then the end
        deadline = time.monotonic() + DEADLINE_S
        while not closed and time.monotonic() < deadline:
            time.sleep(0.05)
        time.sleep(0.2)  # a second close would come straight after the first
        assert closed == [1]
    finally:
        server.shutdown()
        server.server_close()
        thread.join(5)
