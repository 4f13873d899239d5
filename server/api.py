"""The authoring API: ``/api/`` and a dataset's preset library (docs/serving.md).

- ``GET /api/`` → ``{"authoring": true|false, "annotations": true}`` (whether writes are
  possible; the annotation routes are :mod:`.annotations_api`'s);
- ``GET /api/datasets/<name>/presets`` → the dataset's preset library (an empty one if none);
- ``PUT /api/datasets/<name>/presets`` with ``Authorization: Bearer TOKEN`` and a library as
  the JSON body → ``{"presets": N}`` once the dataset (``lanterna.json``, ``presets.json``,
  ``manifest.json``) is rewritten atomically under its lock.

A write is refused before anything is read when no token is configured (403), when the request
comes from another origin (its ``Origin`` header, if any, is not this server's scheme://host:
403), or when the token is missing or wrong (401, ``WWW-Authenticate: Bearer``); a body over
:data:`MAX_BODY` is 413, an invalid library 400 naming the JSON path. Every error is one line,
``{"error": "…"}``. The config key ``AUTHORING_TOKEN`` holds the token (:mod:`.auth`).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from flask import Blueprint, Flask, Response, current_app, request

from lanterna.errors import LanternaInputError
from lanterna.tiler.presets.store import (
    DatasetBusyError,
    PresetError,
    dataset_library,
    store_library,
)

from .auth import bearer_matches
from .safe_path import contained_file

#: The largest request body accepted, in bytes.
MAX_BODY = 1 << 20
api = Blueprint("api", __name__, url_prefix="/api")


def init_app(app: Flask) -> None:
    """Register the API on ``app`` (``AUTHORING_TOKEN`` defaults to None: read-only)."""
    app.config.setdefault("AUTHORING_TOKEN", None)
    app.register_blueprint(api)


def json_error(status: int, message: str, **headers: str) -> Response:
    """A one-line JSON error ``{"error": message}``."""
    resp = Response(json.dumps({"error": " ".join(message.split())}) + "\n", status=status,
                    mimetype="application/json")
    resp.headers.update(headers)
    resp.cache_control.no_store = True
    return resp


def json_response(doc: Any, status: int = 200) -> Response:
    """A JSON document, never cached."""
    resp = Response(json.dumps(doc) + "\n", status=status, mimetype="application/json")
    resp.cache_control.no_store = True
    return resp


def refuse_write() -> Response | None:
    """The error response for a write this request may not make, or None if it may.

    403 when no token is configured or the ``Origin`` is not this server's; 401 (with
    ``WWW-Authenticate: Bearer``) when the token is missing or wrong. Nothing of the body is read.
    """
    token = current_app.config["AUTHORING_TOKEN"]
    if not token:
        return json_error(403, "authoring is off: this server has no authoring token "
                          "(lanterna serve --authoring-token-file FILE)")
    origin = request.headers.get("Origin")
    own = request.host_url.rstrip("/")
    if origin is not None and origin.rstrip("/") != own:
        return json_error(403, f"cross-origin write refused (Origin {origin!r} is not {own})")
    if not bearer_matches(request.headers.get("Authorization"), token):
        return json_error(401, "a valid authoring token is needed (Authorization: Bearer "
                          "TOKEN)", **{"WWW-Authenticate": 'Bearer realm="lanterna"'})
    return None


@api.get("/")
def index() -> Response:
    return json_response({"authoring": bool(current_app.config["AUTHORING_TOKEN"]),
                          "annotations": True})


@api.get("/datasets/<name>/presets")
def get_presets(name: str) -> Response:
    dataset = dataset_path(name)
    if dataset is None:
        return json_error(404, f"no dataset {name!r}")
    try:
        return json_response(dataset_library(dataset))
    except LanternaInputError as err:
        return json_error(500, str(err))


@api.put("/datasets/<name>/presets")
def put_presets(name: str) -> Response:
    refused = refuse_write()
    if refused is not None:
        return refused
    dataset = dataset_path(name)
    if dataset is None:
        return json_error(404, f"no dataset {name!r}")
    if request.content_length is not None and request.content_length > MAX_BODY:
        return json_error(413, f"the body is over {MAX_BODY} bytes")
    body = request.stream.read(MAX_BODY + 1)
    if len(body) > MAX_BODY:
        return json_error(413, f"the body is over {MAX_BODY} bytes")
    try:
        doc = json.loads(body.decode("utf-8"), parse_constant=refuse_constant)
    except (UnicodeDecodeError, ValueError, RecursionError) as err:
        return json_error(400, f"the body is not valid JSON ({str(err).splitlines()[0][:120]})")
    try:
        library = store_library(dataset, doc, source="presets.json")
    except PresetError as err:
        return json_error(400, str(err))
    except DatasetBusyError as err:
        return json_error(503, str(err), **{"Retry-After": "5"})
    except LanternaInputError as err:  # a write error: nothing was changed
        current_app.logger.error("%s", err)
        return json_error(500, str(err))
    return json_response({"presets": len(library["presets"])})


def dataset_path(name: str) -> Path | None:
    """The dataset ``name`` of the data root (its link, as writers use it), or None."""
    root = Path(current_app.config["DATA_ROOT"])
    if name.startswith(".") or "/" in name or contained_file(root, f"{name}/lanterna.json") is None:
        return None
    return root / name


def refuse_constant(name: str) -> float:
    """``json.loads``'s ``parse_constant``: NaN and Infinity are not JSON numbers."""
    raise ValueError(f"{name} is not a JSON number")
