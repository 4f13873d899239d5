"""Run the app under gunicorn: ``lanterna serve ROOT --workers N``, or any WSGI server.

Two entry points:

- :func:`run_gunicorn` starts gunicorn in this process (the process becomes gunicorn's
  arbiter and forks ``workers`` worker processes), with settings chosen for serving many small
  static tiles (:func:`gunicorn_settings`).
- :func:`app_from_env` is an app factory for other deployments, reading the data root from
  ``LANTERNA_DATA_ROOT``::

      LANTERNA_DATA_ROOT=/srv/datasets gunicorn -k gthread --threads 8 -w 4 \\
          'lanterna.server.wsgi:app_from_env()'

Settings (see :func:`gunicorn_settings`): ``gthread`` workers, each with a pool of threads, so a
worker keeps serving while one thread waits on disk or a slow client and HTTP keep-alive
connections (what browsers and OpenSeadragon use) cost no worker; the app is loaded once before
forking (``preload_app``), so a bad data root fails at start; tile files go out with
``sendfile``; no access log unless asked (one line per tile is noise and costs time); gunicorn's
control socket is off (no files under ``$HOME``).
"""

from __future__ import annotations

import os
import socket
from pathlib import Path
from typing import Any

from flask import Flask
from gunicorn.app.base import BaseApplication

from .app import create_app
from .auth import authoring_token

#: Threads per gthread worker (``--threads``).
DEFAULT_THREADS = 8


def app_from_env() -> Flask:
    """Create the app for the data root in ``LANTERNA_DATA_ROOT`` (a WSGI app factory), with
    the authoring token of ``LANTERNA_AUTHORING_TOKEN`` if set (:mod:`.auth`)."""
    root = os.environ.get("LANTERNA_DATA_ROOT")
    if not root:
        raise RuntimeError("set LANTERNA_DATA_ROOT to the folder of datasets")
    return create_app({"DATA_ROOT": root,
                       "AUTHORING_TOKEN": authoring_token(None, os.environ)})


def gunicorn_settings(host: str, port: int, workers: int,
                      threads: int = DEFAULT_THREADS) -> dict[str, Any]:
    """Return the gunicorn settings ``lanterna serve --workers`` uses.

    ``timeout`` (30 s) restarts a worker that stops answering its arbiter; ``keepalive`` (5 s)
    keeps idle client connections open between a viewer's tile bursts; ``graceful_timeout``
    (10 s) bounds how long a stop waits for requests in flight.
    """
    if workers < 1 or threads < 1:
        raise ValueError("workers and threads must be at least 1")
    return {
        "bind": [f"{host}:{port}"],
        "workers": workers,
        "worker_class": "gthread",
        "threads": threads,
        "keepalive": 5,
        "timeout": 30,
        "graceful_timeout": 10,
        "backlog": 2048,
        "preload_app": True,
        "sendfile": True,
        "accesslog": None,
        "errorlog": "-",
        "loglevel": "warning",
        "proc_name": "lanterna",
        "control_socket_disable": True,
    }


class _Gunicorn(BaseApplication):  # type: ignore[misc]  # gunicorn ships no type hints
    """gunicorn's embedding API: a fixed app and settings, no command-line parsing."""

    def __init__(self, app: Flask, settings: dict[str, Any]) -> None:
        self._app = app
        self._settings = settings
        super().__init__()

    def load_config(self) -> None:
        for key, value in self._settings.items():
            self.cfg.set(key, value)

    def load(self) -> Flask:
        return self._app


def run_gunicorn(root: Path, listener: socket.socket, workers: int,
                 threads: int = DEFAULT_THREADS, config: dict[str, object] | None = None, *,
                 access_log: bool = False) -> None:
    """Serve the datasets in ``root`` with gunicorn on ``listener`` until stopped (SIGINT, SIGTERM).

    ``listener`` is bound and listening already (:func:`lanterna.server.local.listen`); gunicorn
    takes it over. ``config`` adds app settings (e.g. the ``IIIF_*`` limits); ``access_log``
    logs every request to stdout. The app (its config, the authoring token included) is made
    here, before gunicorn forks its workers, which inherit it. Does not return normally:
    gunicorn's arbiter exits the process when it stops.
    """
    app = create_app({**(config or {}), "DATA_ROOT": root})
    host, port = listener.getsockname()[:2]
    settings = gunicorn_settings(host, port, workers, threads)
    settings["bind"] = [f"fd://{listener.detach()}"]  # bound already: gunicorn takes it over
    if access_log:
        settings["accesslog"] = "-"
    _Gunicorn(app, settings).run()
