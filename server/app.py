"""The Flask application: static IIIF trees, manifests and the viewer, for local deployment.

``create_app(config)`` is the factory; routes stay thin. Files are only ever served through
``send_from_directory`` (which refuses paths escaping the folder), and JSON documents get the
dataset's recorded ``baseUrl`` rewritten to the URL of the request, so every IIIF ``id``
matches the URL it was fetched from.
"""

from __future__ import annotations

import html
import json
from pathlib import Path
from typing import Any

from flask import Flask, Response, abort, redirect, request, send_from_directory
from werkzeug.security import safe_join
from werkzeug.wrappers import Response as BaseResponse

IMAGE_CONTEXT = "http://iiif.io/api/image/3/context.json"
PRESENTATION_CONTEXT = "http://iiif.io/api/presentation/3/context.json"
REPO_VIEWER = Path(__file__).resolve().parent.parent / "plugin" / "dist" / "viewer"
_MEDIA = {".png": "image/png", ".jpg": "image/jpeg", ".jpeg": "image/jpeg", ".json": None}


def create_app(config: dict[str, Any] | None = None) -> Flask:
    """Create the app.

    Config keys: ``DATA_ROOT`` (folder of datasets, required), ``VIEWER_DIR`` (the built viewer
    page, default ``plugin/dist/viewer`` of this checkout).
    """
    app = Flask(__name__)
    app.config["VIEWER_DIR"] = str(REPO_VIEWER)
    app.config.update(config or {})
    if "DATA_ROOT" not in app.config:
        raise ValueError("create_app needs DATA_ROOT")
    root = Path(app.config["DATA_ROOT"]).resolve()
    app.config["DATA_ROOT"] = str(root)

    @app.after_request
    def cors(resp: Response) -> Response:
        resp.headers["Access-Control-Allow-Origin"] = "*"
        if request.method == "OPTIONS":
            resp.headers["Access-Control-Allow-Methods"] = "GET, HEAD, OPTIONS"
            resp.headers["Access-Control-Allow-Headers"] = "Accept, Content-Type, Range"
        return resp

    @app.get("/")
    def index() -> Response:
        return Response(_index_html(root), mimetype="text/html")

    @app.get("/viewer/")
    @app.get("/viewer/<path:path>")
    def viewer(path: str = "index.html") -> Response:
        return send_from_directory(app.config["VIEWER_DIR"], path)

    @app.get("/datasets/<path:path>")
    def datasets(path: str) -> Response | BaseResponse:
        parts = path.strip("/").split("/")
        full = safe_join(str(root), path)
        if full is None:
            abort(404)
        target = Path(full)
        if target.is_dir():
            # An image service's base URI redirects to its info.json (IIIF baseUriRedirect).
            if len(parts) == 3 and parts[1] == "iiif" and (target / "info.json").is_file():
                return redirect(f"{request.base_url.rstrip('/')}/info.json", code=303)
            abort(404)
        if not target.is_file() or target.suffix.lower() not in _MEDIA:
            abort(404)
        if target.suffix.lower() == ".json":
            return _json_response(root, parts[0], target)
        return send_from_directory(root, path, mimetype=_MEDIA[target.suffix.lower()],
                                   max_age=3600)

    return app


def _json_response(root: Path, dataset: str, target: Path) -> Response:
    """Serve a JSON document with the dataset's base URL rewritten to the request's."""
    text = target.read_text()
    recorded = _recorded_base(root / dataset)
    served = request.url_root.rstrip("/") + "/datasets"
    if recorded and recorded != served:
        text = text.replace(recorded + "/", served + "/")
    context = IMAGE_CONTEXT if target.name == "info.json" else PRESENTATION_CONTEXT
    if "application/ld+json" in request.headers.get("Accept", ""):
        mimetype = f'application/ld+json;profile="{context}"'
    else:
        mimetype = "application/json"
    resp = Response(text, mimetype=mimetype)
    resp.headers["Content-Type"] = mimetype
    return resp


def _recorded_base(dataset_dir: Path) -> str | None:
    try:
        base = json.loads((dataset_dir / "lanterna.json").read_text())["baseUrl"]
    except (OSError, ValueError, KeyError, TypeError):
        return None
    return str(base).rstrip("/")


def _index_html(root: Path) -> str:
    rows = []
    for desc_path in sorted(root.glob("*/lanterna.json")):
        try:
            desc = json.loads(desc_path.read_text())
        except ValueError:
            continue
        name = desc_path.parent.name
        manifest = f"{request.url_root}datasets/{name}/manifest.json"
        rows.append(
            f'<li><a href="viewer/?manifest={html.escape(manifest)}">'
            f"{html.escape(str(desc.get('label', name)))}</a> "
            f'<small>(<a href="datasets/{html.escape(name)}/manifest.json">IIIF manifest</a>, '
            f"{desc.get('width')}×{desc.get('height')})</small></li>"
        )
    items = "\n".join(rows) or "<li>No datasets yet: <code>lanterna import FILE -o DIR</code></li>"
    return (
        "<!doctype html><meta charset=utf-8><title>Lanterna</title>"
        "<style>body{font:16px system-ui;margin:2em;max-width:50em}</style>"
        f"<h1>Lanterna</h1><p>Datasets in <code>{html.escape(str(root))}</code>:</p>"
        f"<ul>{items}</ul>"
    )
