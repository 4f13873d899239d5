"""The annotation routes of the authoring API: a layer's patch store (docs/serving.md).

Under ``/api/datasets/<name>/layers/<layer>/``: ``patches`` (GET list, POST create),
``patches/<id>`` (GET, PUT, DELETE), ``patches/<id>/image`` (GET), ``levels/<L>`` (PUT) and
``status`` (GET). Reads are public; writes are refused as the presets' are
(:func:`~.api.refuse_write`: 403 / 401 before the body is read), then 404 for an unknown dataset,
layer or patch, 413 for a body over :data:`MAX_UPLOAD` or a PNG too large by its header, 400 for
anything else wrong, naming it — checked before anything is stored — and 503 (``Retry-After``)
when the store's lock cannot be had. After every change the process's
:class:`~.rebuilder.Rebuilder` brings the layer's pyramid up to date in the background.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path
from typing import Any

from flask import Blueprint, Flask, Response, current_app, request, send_file
from werkzeug.exceptions import RequestEntityTooLarge

from lanterna.errors import LanternaInputError
from lanterna.tiler.overlays import store
from lanterna.tiler.overlays.published import published_layer

from .api import dataset_path, json_error, json_response, refuse_constant, refuse_write
from .rebuilder import Rebuilder, status

#: The largest patch upload (multipart body), in bytes.
MAX_UPLOAD = 16 << 20
#: The largest JSON body of a level-texts write, in bytes.
MAX_TEXTS = 1 << 20
_EXT = "lanterna.rebuilder"
routes = Blueprint("annotations", __name__,
                        url_prefix="/api/datasets/<name>/layers/<layer>")


def init_app(app: Flask) -> None:
    """Register the routes and the process's rebuilder (``REBUILD_INLINE``: rebuild in the
    request, for tests)."""
    app.config.setdefault("REBUILD_INLINE", False)
    app.extensions[_EXT] = Rebuilder(inline=bool(app.config["REBUILD_INLINE"]))
    app.register_blueprint(routes)


def _rebuilder() -> Rebuilder:
    found: Rebuilder = current_app.extensions[_EXT]
    return found


class _Refused(Exception):
    def __init__(self, response: Response) -> None:
        self.response = response


def _target(name: str, layer: str) -> Path:
    """The dataset of the request, if it has ``layer`` (else a 404 is raised as _Refused)."""
    dataset = dataset_path(name)
    if dataset is None:
        raise _Refused(json_error(404, f"no dataset {name!r}"))
    try:
        published_layer(dataset, layer)
        store.store_dir(dataset, layer)
    except LanternaInputError:
        raise _Refused(json_error(404, f"no layer {layer!r} in dataset {name!r}")) from None
    return dataset


def _answer(action: Callable[[], Response]) -> Response:
    """Run a route's ``action``, turning the store's errors into one-line JSON errors."""
    try:
        return action()
    except _Refused as refused:
        return refused.response
    except store.PatchError as err:
        return json_error(413 if err.too_large else 400, str(err))
    except store.NoSuchPatch as err:
        return json_error(404, str(err).rsplit(": ", 1)[-1])
    except store.DatasetBusyError as err:
        return json_error(503, str(err), **{"Retry-After": "2"})
    except RequestEntityTooLarge:
        return json_error(413, f"the body is over {MAX_UPLOAD} bytes")
    except LanternaInputError as err:  # a write error: nothing was changed
        current_app.logger.error("%s", err)
        return json_error(500, str(err))


def _write(name: str, layer: str, action: Callable[[Path], Response]) -> Response:
    """A write: refused (403/401) before the body is read, then the target, then ``action``."""
    refused = refuse_write()
    if refused is not None:
        return refused

    def run() -> Response:
        dataset = _target(name, layer)
        if request.content_length is not None and request.content_length > MAX_UPLOAD:
            raise RequestEntityTooLarge()
        request.max_content_length = MAX_UPLOAD
        return action(dataset)

    return _answer(run)


def _with_status(doc: dict[str, Any], dataset: Path, layer: str, code: int = 200) -> Response:
    return json_response({**doc, "status": status(_rebuilder(), dataset, layer)}, code)


def _upload() -> tuple[dict[str, Any] | None, bytes | None]:
    """The ``meta`` (a JSON object) and ``image`` (bytes) parts of a multipart body."""
    if request.is_json:
        body = request.get_data(cache=False)
        return _meta_json(body.decode("utf-8", "replace")), None
    meta_text = request.form.get("meta")
    upload = request.files.get("image")
    image = upload.read(MAX_UPLOAD + 1) if upload is not None else None
    if image is not None and len(image) > MAX_UPLOAD:
        raise RequestEntityTooLarge()
    return (None if meta_text is None else _meta_json(meta_text)), image


def _meta_json(text: str) -> dict[str, Any]:
    try:
        meta = json.loads(text, parse_constant=refuse_constant)
    except (ValueError, RecursionError) as err:
        raise store.PatchError("meta", f"not valid JSON ({str(err).splitlines()[0][:120]})"
                               ) from None
    if not isinstance(meta, dict):
        raise store.PatchError("meta", "expected a JSON object")
    return meta


# -- reads ------------------------------------------------------------------------------------
@routes.get("/patches")
def list_patches(name: str, layer: str) -> Response:
    def run() -> Response:
        dataset = _target(name, layer)
        return _with_status({"layer": layer, "patches": store.list_patches(dataset, layer),
                             "levels": store.level_texts(dataset, layer)}, dataset, layer)
    return _answer(run)


@routes.get("/patches/<patch_id>")
def get_patch(name: str, layer: str, patch_id: str) -> Response:
    return _answer(lambda: json_response(store.get_patch(_target(name, layer), layer,
                                                         patch_id)))


@routes.get("/patches/<patch_id>/image")
def get_image(name: str, layer: str, patch_id: str) -> Response:
    def run() -> Response:
        path = store.patch_image(_target(name, layer), layer, patch_id)
        try:
            resp = send_file(path, mimetype="image/png", conditional=True, max_age=0)
        except OSError:  # deleted (or republished) since it was listed
            raise store.NoSuchPatch(path, f"no patch {patch_id!r} in layer {layer!r}") from None
        resp.cache_control.no_cache = True
        return resp
    return _answer(run)


@routes.get("/status")
def get_status(name: str, layer: str) -> Response:
    def run() -> Response:
        dataset = _target(name, layer)
        return json_response(status(_rebuilder(), dataset, layer))
    return _answer(run)


# -- writes -----------------------------------------------------------------------------------
@routes.post("/patches")
def create_patch(name: str, layer: str) -> Response:
    def action(dataset: Path) -> Response:
        meta, image = _upload()
        if meta is None or image is None:
            raise store.PatchError("upload", "expected a multipart body with \"meta\" (JSON) "
                                   "and \"image\" (PNG)")
        record = store.add_patch(dataset, layer, image, meta)
        _rebuilder().request(dataset, layer)
        return _with_status({"patch": record}, dataset, layer, 201)
    return _write(name, layer, action)


@routes.put("/patches/<patch_id>")
def replace_patch(name: str, layer: str, patch_id: str) -> Response:
    def action(dataset: Path) -> Response:
        meta, image = _upload()
        if meta is None and image is None:
            raise store.PatchError("upload", "expected \"meta\" (JSON) and/or \"image\" (PNG)")
        record = store.replace_patch(dataset, layer, patch_id, image=image, meta=meta)
        _rebuilder().request(dataset, layer)
        return _with_status({"patch": record}, dataset, layer)
    return _write(name, layer, action)


@routes.delete("/patches/<patch_id>")
def delete_patch(name: str, layer: str, patch_id: str) -> Response:
    def action(dataset: Path) -> Response:
        store.delete_patch(dataset, layer, patch_id)
        _rebuilder().request(dataset, layer)
        return _with_status({"deleted": patch_id}, dataset, layer)
    return _write(name, layer, action)


@routes.put("/levels/<int:level>")
def put_level(name: str, layer: str, level: int) -> Response:
    def action(dataset: Path) -> Response:
        body = request.stream.read(MAX_TEXTS + 1)
        if len(body) > MAX_TEXTS:  # its own limit, named (not the upload's)
            raise store.PatchError("level texts", f"the body is over {MAX_TEXTS} bytes",
                                   too_large=True)
        texts = _meta_json(body.decode("utf-8", "replace"))
        store.set_level_texts(dataset, layer, {str(level): texts})
        _rebuilder().request(dataset, layer)
        text = store.level_texts(dataset, layer)[str(level)]
        return _with_status({"level": level, **text}, dataset, layer)
    return _write(name, layer, action)
