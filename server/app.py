"""The Flask application: static IIIF trees, manifests and the viewer, for local deployment.

``create_app(config)`` is the factory; routes stay thin. Files are only ever served after
:func:`~lanterna.server.safe_path.contained_file` has resolved them (symlinks included) inside
the data root, and JSON documents get the dataset's recorded ``baseUrl`` rewritten to the URL of
the request, so every IIIF ``id`` matches the URL it was fetched from. The level-1 image server
over pyramidal TIFFs lives in :mod:`lanterna.server.image_api` (``/iiif/3/…``), the authoring
API in :mod:`lanterna.server.api` and :mod:`lanterna.server.annotations_api` (``/api/…``);
errors are short plain text (:mod:`lanterna.server.errors`).
"""

from __future__ import annotations

import html
import json
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

from flask import Flask, Response, abort, redirect, request, send_from_directory
from werkzeug.exceptions import NotFound
from werkzeug.wrappers import Response as BaseResponse

from lanterna.tiler.entry_names import is_version
from lanterna.tiler.iiif.spec import IMAGE_CONTEXT, PRESENTATION_CONTEXT

from . import annotations_api, api, image_api
from .errors import plain_error, register_error_handlers
from .safe_path import contained_dir, contained_file, raw_path_is_safe

#: The viewer page a wheel carries (setup.py copies ``plugin/dist/viewer`` there).
PACKAGED_VIEWER = Path(__file__).resolve().parent / "viewer"
#: The viewer page of a checkout (``npm run build``), for editable installs.
REPO_VIEWER = Path(__file__).resolve().parent.parent / "plugin" / "dist" / "viewer"
#: How to build the viewer when it is missing.
BUILD_VIEWER = "run `make build` in the Lanterna checkout"
_MEDIA = {".png": "image/png", ".jpg": "image/jpeg", ".jpeg": "image/jpeg", ".webp": "image/webp",
          ".json": None}


def default_viewer() -> Path:
    """Return the built viewer: the packaged one if present, else the checkout's (may be absent)."""
    return PACKAGED_VIEWER if (PACKAGED_VIEWER / "index.html").is_file() else REPO_VIEWER


def create_app(config: dict[str, Any] | None = None) -> Flask:
    """Create the app.

    Config keys: ``DATA_ROOT`` (folder of datasets, required), ``VIEWER_DIR`` (the built viewer
    page, default :func:`default_viewer`), the image server's ``IIIF_*``
    limits (:data:`lanterna.server.image_api.DEFAULTS`, docs/serving.md), and
    ``AUTHORING_TOKEN`` (the authoring API's token, :mod:`lanterna.server.api`; None: read-only),
    ``REBUILD_INLINE`` (rebuild overlays in the request instead of in the background: tests).
    """
    app = Flask(__name__)
    app.url_map.merge_slashes = False  # "//x" is a bad path (404), not a redirect to "/x"
    app.config["VIEWER_DIR"] = str(default_viewer())
    app.config.update(config or {})
    if "DATA_ROOT" not in app.config:
        raise ValueError("create_app needs DATA_ROOT")
    root = Path(app.config["DATA_ROOT"]).resolve()
    app.config["DATA_ROOT"] = str(root)
    register_error_handlers(app)
    image_api.init_app(app)
    api.init_app(app)
    annotations_api.init_app(app)

    @app.before_request
    def refuse_hidden_separators() -> None:
        # %2F, %5C or %00 in the raw path would reach routing decoded: refuse them outright.
        if not raw_path_is_safe(request.environ):
            abort(404)

    @app.after_request
    def cors(resp: Response) -> Response:
        if request.path.startswith("/api/") and request.method not in ("GET", "HEAD"):
            return resp  # writes are same-origin only: no CORS for them, preflights included
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
        folder = Path(app.config["VIEWER_DIR"])
        if not (folder / "index.html").is_file():
            return plain_error(404, f"the viewer is not built ({BUILD_VIEWER})")
        return send_from_directory(folder, path)

    @app.get("/datasets/<path:path>")
    def datasets(path: str) -> Response | BaseResponse:
        parts = path.strip("/").split("/")
        folder = contained_dir(root, path.rstrip("/"))
        if folder is not None:
            # An image service's base URI redirects to its info.json (IIIF baseUriRedirect).
            if len(parts) == 3 and parts[1] == "iiif" and (folder / "info.json").is_file():
                return redirect(f"{request.base_url.rstrip('/')}/info.json", code=303)
            abort(404)  # no directory listings
        target = _served_file(root, path)
        try:
            return _file_response(root, target)
        except (FileNotFoundError, NotFound):
            # The dataset was republished between resolving its link and opening the file, and
            # its previous version removed: resolve the link again, once.
            return _file_response(root, _served_file(root, path))

    return app


def _served_file(root: Path, path: str) -> Path:
    """Return the resolved file the request ``path`` names, or abort with 404."""
    target = contained_file(root, path)
    if target is None or Path(path).suffix.lower() not in _MEDIA \
            or target.suffix.lower() not in _MEDIA:
        abort(404)
    return target


def _file_response(root: Path, target: Path) -> BaseResponse:
    """Serve the resolved file ``target`` of the data root (JSON rewritten, tiles as they are)."""
    if target.suffix.lower() == ".json":
        return _json_response(root, target)
    # ETag (mtime-size-hash), Last-Modified and 304s come from send_file (conditional=True).
    return send_from_directory(root, str(target.relative_to(root)),
                               mimetype=_MEDIA[target.suffix.lower()], max_age=3600)


def _json_response(root: Path, target: Path) -> BaseResponse:
    """Serve a JSON document with the dataset's base URL rewritten to the request's."""
    # The description of the version the document belongs to (the dataset's link resolved),
    # read before the document: a version removed after it fails on the document's read, one
    # being removed before it fails here, and both take the caller's one retry, never a
    # document served with its recorded base.
    recorded = _recorded_base(root / target.relative_to(root).parts[0])
    text = target.read_text()
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
    resp.last_modified = datetime.fromtimestamp(int(target.stat().st_mtime), tz=UTC)
    resp.cache_control.max_age = 60
    resp.vary.add("Accept")
    resp.add_etag()  # from the body, which depends on the request URL and Accept
    return resp.make_conditional(request)


#: ``lanterna.json`` path → ((inode, size, mtime), its ``baseUrl``): the description is parsed once
#: per version, not on every JSON request (it holds whole PCA bases, ~80 KB for the demo).
_BASES: dict[Path, tuple[tuple[int, int, int], str | None]] = {}
_MAX_BASES = 1024


def _recorded_base(dataset_dir: Path) -> str | None:
    """The ``baseUrl`` of the dataset folder's ``lanterna.json``, or ``None`` if it has none.

    Raises ``FileNotFoundError`` if the folder is a published version (``.NAME.v-ID``, which
    always has its description) whose description is gone: the version is being removed.
    """
    path = dataset_dir / "lanterna.json"
    version = is_version(dataset_dir.name)
    try:
        real = path.resolve()
        st = real.stat()
        cached = _BASES.get(real)
        stamp = (st.st_ino, st.st_size, st.st_mtime_ns)
        if cached is not None and cached[0] == stamp:
            return cached[1]
        text = real.read_text()
    except OSError:
        if version:
            raise FileNotFoundError(path) from None
        return None
    try:
        base: str | None = str(json.loads(text)["baseUrl"]).rstrip("/")
    except (ValueError, KeyError, TypeError):
        base = None
    if len(_BASES) >= _MAX_BASES:
        _BASES.clear()
    _BASES[real] = (stamp, base)
    return base


def _index_html(root: Path) -> str:
    rows = []
    for name in sorted(p.name for p in root.iterdir()):
        # only what /datasets serves: no hidden entries (a dataset's versions, a killed
        # writer's temporary folders), nothing a link takes outside the root
        desc_path = contained_file(root, f"{name}/lanterna.json")
        if desc_path is None:
            continue
        try:
            desc = json.loads(desc_path.read_text())
        except (OSError, ValueError):
            continue
        manifest = f"{request.url_root}datasets/{name}/manifest.json"
        rows.append(
            f'<li><a href="viewer/?manifest={html.escape(manifest)}">'
            f"{html.escape(str(desc.get('label', name)))}</a> "
            f'<small>(<a href="viewer/mirador.html?manifest={html.escape(manifest)}">'
            "in Mirador</a>, "
            f'<a href="datasets/{html.escape(name)}/manifest.json">IIIF manifest</a>, '
            f"{desc.get('width')}×{desc.get('height')})</small></li>"
        )
    items = "\n".join(rows) or "<li>No datasets yet: <code>lanterna import FILE -o DIR</code></li>"
    return (
        "<!doctype html><meta charset=utf-8><title>Lanterna</title>"
        "<style>body{font:16px system-ui;margin:2em;max-width:50em}</style>"
        f"<h1>Lanterna</h1><p>Datasets in <code>{html.escape(str(root))}</code>:</p>"
        f"<ul>{items}</ul>"
    )
