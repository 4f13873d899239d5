"""IIIF Image API 3 level-1 image service (plus level-2 extras) over one pyramidal TIFF per image.

URLs (``docs/serving.md``): ``/iiif/3/{dataset}/{image}`` is the base URI (303 to info.json),
``…/info.json`` the image information, ``…/{region}/{size}/{rotation}/{quality}.{format}`` an
image. ``{dataset}`` and ``{image}`` are names of ``[A-Za-z0-9_-]`` (so never need escaping),
and the file read is ``{DATA_ROOT}/{dataset}/tiff/{image}.tif``, written by ``--tiff``.

Every response carries ``Link: <…/level1.json>;rel="profile"``; images also carry their canonical
URL as ``rel="canonical"`` (non-canonical forms are served, not redirected). Responses have a
strong ``ETag`` (file identity + canonical request), ``Last-Modified`` (the TIFF's mtime) and
``Cache-Control``; a matching ``If-None-Match`` or ``If-Modified-Since`` gives 304 before any
pixel is decoded. Sizes over the limits are refused with 400 before any pixel work; the limits
published are at most what every output format can encode (:meth:`Limits.encodable`: WebP's
16383 px), so ``max`` and every size within the limits can be served in every format.
"""

from __future__ import annotations

import functools
import hashlib
import json
import re
from collections.abc import Callable
from datetime import UTC, datetime
from functools import lru_cache
from pathlib import Path
from typing import Any, TypeVar, cast

import pyvips
from flask import Blueprint, Flask, Response, current_app, redirect, request, url_for
from werkzeug.http import is_resource_modified
from werkzeug.wrappers import Response as BaseResponse

from lanterna.tiler.iiif import geometry as geo
from lanterna.tiler.iiif.spec import IMAGE_CONTEXT, IMAGE_PROTOCOL, image_profile_uri

from . import image_response
from .errors import plain_error
from .image_request import (
    FORMATS,
    MAX_SIDE,
    Limits,
    RequestError,
    max_size,
    parse_image_request,
)
from .safe_path import contained_file

PROFILE = "level1"
PROFILE_URI = image_profile_uri(PROFILE)
EXTRA_FEATURES = ["regionByPct", "sizeByPct", "sizeByConfinedWh", "rotationBy90s", "mirroring",
                  "profileLinkHeader", "canonicalLinkHeader"]
EXTRA_QUALITIES = ["color", "gray", "bitonal"]
#: Dataset tile formats whose TIFF holds the data losslessly: served as lossless WebP, and the
#: format itself is the info.json's ``preferredFormats``.
LOSSLESS_FORMATS = ("png", "webp")
#: Config keys and their defaults (documented in docs/serving.md).
DEFAULTS: dict[str, Any] = {
    "IIIF_MAX_WIDTH": MAX_SIDE,
    "IIIF_MAX_HEIGHT": MAX_SIDE,
    "IIIF_MAX_AREA": 16 * 1024 * 1024,
    "IIIF_UPSCALING": False,
    "IIIF_TILE_SIZE": 256,
    "IIIF_MAX_AGE": 86400,
}
#: The pixels read from the chosen level may be this many times ``maxArea``: a pyramid needs at
#: most 2×2 level pixels per output pixel, so only a TIFF without a usable pyramid or a strongly
#: distorting ``w,h`` on a huge image reads more; that is refused (400) rather than decoded.
WORK_FACTOR = 4
_NAME = re.compile(r"^[A-Za-z0-9_-]{1,128}$")

bp = Blueprint("iiif_image", __name__, url_prefix="/iiif/3")


def init_app(app: Flask) -> None:
    """Register the image API on ``app`` with the ``IIIF_*`` config defaults filled in."""
    for key, value in DEFAULTS.items():
        app.config.setdefault(key, value)
    app.register_blueprint(bp)


def _limits() -> Limits:
    """The configured limits, sides capped at what every output format can encode."""
    cfg = current_app.config
    return Limits(int(cfg["IIIF_MAX_WIDTH"]), int(cfg["IIIF_MAX_HEIGHT"]),
                  int(cfg["IIIF_MAX_AREA"]), bool(cfg["IIIF_UPSCALING"])).encodable()


_View = TypeVar("_View", bound=Callable[..., Response | BaseResponse])


def _once_more_if_replaced(view: _View) -> _View:
    """Run ``view`` again, once, if reading its TIFF failed.

    A dataset republished during the request has its previous version (the TIFF just resolved)
    removed; the second run resolves the dataset's link to the new version. A TIFF that cannot
    be read at all fails twice, and is a 500 as before.
    """
    @functools.wraps(view)
    def run(*args: Any, **kwargs: Any) -> Response | BaseResponse:
        try:
            return view(*args, **kwargs)
        except (OSError, pyvips.Error):
            return view(*args, **kwargs)

    return cast(_View, run)


def _tiff(dataset: str, image: str) -> Path:
    """Return the TIFF of ``dataset/image`` inside DATA_ROOT, or raise a 404 RequestError."""
    if not _NAME.match(dataset) or not _NAME.match(image):
        raise RequestError(404, "no such image")
    root = Path(current_app.config["DATA_ROOT"])
    path = contained_file(root, f"{dataset}/tiff/{image}.tif")
    if path is None:
        raise RequestError(404, "no such image")
    return path


@lru_cache(maxsize=256)
def _image_formats(desc_path: Path, _mtime_ns: int) -> dict[str, str]:
    try:
        desc = json.loads(desc_path.read_text())
        return {str(k): str(v.get("format", "jpg")) for k, v in desc["images"].items()}
    except (OSError, ValueError, KeyError, TypeError, AttributeError):
        return {}


def _source_format(tiff: Path, image: str) -> str:
    """Return the dataset format of the image's tiles (``png``, ``webp`` or ``jpg``)."""
    desc = tiff.parent.parent / "lanterna.json"
    try:
        mtime = desc.stat().st_mtime_ns
    except OSError:
        return "jpg"
    return _image_formats(desc, mtime).get(image, "jpg")


def _etag(tiff: Path, what: str) -> str:
    st = tiff.stat()
    key = f"{st.st_dev}:{st.st_ino}:{st.st_size}:{st.st_mtime_ns}:{what}"
    return hashlib.sha256(key.encode()).hexdigest()[:32]


def _mtime(path: Path) -> datetime:
    """Return the file's modification time, to the second (the HTTP date precision)."""
    return datetime.fromtimestamp(int(path.stat().st_mtime), tz=UTC)


def _cached(resp: Response | BaseResponse, tiff: Path, etag: str,
            canonical: str | None = None) -> Response | BaseResponse:
    """Add the caching headers and one ``Link`` header (canonical URL first, then profile)."""
    resp.set_etag(etag)
    resp.last_modified = _mtime(tiff)
    resp.headers["Cache-Control"] = f"public, max-age={int(current_app.config['IIIF_MAX_AGE'])}"
    links = ([f'<{canonical}>;rel="canonical"'] if canonical else [])
    resp.headers["Link"] = ", ".join([*links, f'<{PROFILE_URI}>;rel="profile"'])
    return resp


def _not_modified(tiff: Path, etag: str) -> bool:
    return not is_resource_modified(request.environ, etag=etag,
                                    last_modified=_mtime(tiff))


@bp.errorhandler(RequestError)
def _request_error(err: RequestError) -> Response:
    resp = plain_error(err.status, err.message)
    resp.headers["Link"] = f'<{PROFILE_URI}>;rel="profile"'
    return resp


@bp.get("/<dataset>/<image>")
def base(dataset: str, image: str) -> BaseResponse:
    """Redirect the base URI to info.json (303, ``baseUriRedirect``)."""
    _tiff(dataset, image)
    return redirect(url_for(".info", dataset=dataset, image=image), code=303)


def info_document(tiff: Path, image: str, service_id: str, limits: Limits,
                  tile_size: int) -> dict[str, Any]:
    """Return the info.json of the TIFF ``tiff`` served at ``service_id``."""
    width, height = image_response.tiff_levels(tiff)[0]
    factors = geo.scale_factors(width, height, tile_size)
    top = max_size(width, height, limits)
    sizes = [geo.level_size(width, height, f) for f in reversed(factors)]
    formats = [f for f in FORMATS if f != "jpg"]
    doc: dict[str, Any] = {
        "@context": IMAGE_CONTEXT, "id": service_id, "type": "ImageService3",
        "protocol": IMAGE_PROTOCOL, "profile": PROFILE,
        "width": width, "height": height,
        "maxWidth": limits.max_width, "maxHeight": limits.max_height, "maxArea": limits.max_area,
        "sizes": [{"width": w, "height": h} for w, h in sizes if w <= top[0] and h <= top[1]],
        "tiles": [{"width": tile_size, "height": tile_size, "scaleFactors": factors}],
        "extraFormats": formats,
        "extraQualities": EXTRA_QUALITIES,
        "extraFeatures": EXTRA_FEATURES + (["sizeUpscaling"] if limits.upscaling else []),
    }
    source = _source_format(tiff, image)
    if source in LOSSLESS_FORMATS:
        doc["preferredFormats"] = [source]
    return doc


@bp.get("/<dataset>/<image>/info.json")
@_once_more_if_replaced
def info(dataset: str, image: str) -> Response | BaseResponse:
    """Serve info.json (JSON-LD when asked for, with ``id`` = this request's base URI)."""
    tiff = _tiff(dataset, image)
    service_id = url_for(".base", dataset=dataset, image=image, _external=True)
    limits = _limits()
    tile_size = int(current_app.config["IIIF_TILE_SIZE"])
    ld = "application/ld+json" in request.headers.get("Accept", "")
    etag = _etag(tiff, f"info:{service_id}:{limits}:{tile_size}:{PROFILE}:{ld}")
    if _not_modified(tiff, etag):
        return _cached(Response(status=304), tiff, etag)
    doc = info_document(tiff, image, service_id, limits, tile_size)
    mimetype = f'application/ld+json;profile="{IMAGE_CONTEXT}"' if ld else "application/json"
    resp = Response(json.dumps(doc, indent=2, allow_nan=False), mimetype=mimetype)
    resp.headers["Content-Type"] = mimetype
    resp.vary.add("Accept")
    return _cached(resp, tiff, etag)


@bp.get("/<dataset>/<image>/<region>/<size>/<rotation>/<quality_format>")
@_once_more_if_replaced
def image_request(dataset: str, image: str, region: str, size: str, rotation: str,
                  quality_format: str) -> Response | BaseResponse:
    """Serve one image request: parse, check limits, read the right level, encode."""
    tiff = _tiff(dataset, image)
    levels = image_response.tiff_levels(tiff)
    width, height = levels[0]
    limits = _limits()
    req = parse_image_request(region, size, rotation, quality_format, width, height, limits)
    plan = image_response.plan_read(levels, req)
    if plan.w * plan.h > WORK_FACTOR * limits.max_area:
        raise RequestError(400, "no pyramid level of this image is small enough for that size")
    canonical = req.canonical(width, height, limits)
    etag = _etag(tiff, f"image:{canonical}")
    base_uri = url_for(".base", dataset=dataset, image=image, _external=True)
    if _not_modified(tiff, etag):
        resp: Response | BaseResponse = Response(status=304)
    else:
        out = image_response.compute_image(tiff, req, plan)
        lossless = _source_format(tiff, image) in LOSSLESS_FORMATS
        resp = Response(image_response.encode(out, req.format, lossless=lossless),
                        mimetype=FORMATS[req.format])
    return _cached(resp, tiff, etag, f"{base_uri}/{canonical}")
