"""Fetch a whole image from a IIIF Image API (2 or 3) service: its ``info.json`` first, then
``{service}/full/max/0/default.{format}``, the size checked before any pixel is downloaded.

The ``info.json`` is checked against ``tiler/schemas/iiif-image-info.schema.json``; the size of
``max`` is the image's size reduced to the service's ``maxWidth``/``maxHeight``/``maxArea``
(IIIF Image API 3 §4.2), checked against the pixel limit (``--max-pixels``) and bounding the
download (:data:`BYTES_PER_PIXEL` per pixel). The format is the first of the service's
``preferredFormats`` Lanterna decodes, else ``jpg`` (the one every level-0 service serves).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from lanterna.errors import LanternaInputError
from lanterna.tiler.documents import check_document, parse_json
from lanterna.tiler.limits import check_pixels

from .remote import fetch

#: Largest ``info.json`` read.
MAX_INFO_BYTES = 1 << 20
#: Download bound per pixel of ``max`` (16-bit RGBA uncompressed is 8) plus a fixed allowance.
BYTES_PER_PIXEL, SLACK_BYTES = 8, 1 << 20
#: Formats Lanterna decodes, by name, and their file suffixes.
FORMATS = {"png": ".png", "webp": ".webp", "jpg": ".jpg", "tif": ".tif"}
_ACCEPT = {3: 'application/ld+json;profile="http://iiif.io/api/image/3/context.json"',
           0: "application/json"}


@dataclass(frozen=True)
class FullImage:
    """A fetched image: its encoded bytes, format name, size (``max``) and URL."""

    data: bytes
    fmt: str
    width: int
    height: int
    url: str


@dataclass(frozen=True)
class ImageInfo:
    """The parts of a service's ``info.json`` a full download needs."""

    service: str
    width: int
    height: int
    fmt: str


def max_size(info: dict[str, Any]) -> tuple[int, int]:
    """The size ``max`` stands for: the full size within ``maxWidth``/``maxHeight``/``maxArea``."""
    w, h = int(info["width"]), int(info["height"])
    scale = 1.0
    if "maxWidth" in info:
        scale = min(scale, info["maxWidth"] / w)
        scale = min(scale, info.get("maxHeight", info["maxWidth"]) / h)
    elif "maxHeight" in info:
        scale = min(scale, info["maxHeight"] / h)
    if "maxArea" in info:
        scale = min(scale, math.sqrt(info["maxArea"] / (w * h)))
    if scale >= 1.0:
        return w, h
    return max(1, math.floor(w * scale)), max(1, math.floor(h * scale))


def read_info(service: str, where: str) -> ImageInfo:
    """Fetch and check ``{service}/info.json``; ``where`` prefixes its errors (the manifest and
    the JSON path of the service)."""
    url = f"{service.rstrip('/')}/info.json"
    try:
        raw = fetch(url, "a IIIF info.json", max_bytes=MAX_INFO_BYTES,
                    accept=f"{_ACCEPT[3]}, {_ACCEPT[0]};q=0.9")
        info = check_document(parse_json(raw, url), "iiif-image-info", url)
        width, height = max_size(info)
        check_pixels(url, width, height)
    except LanternaInputError as err:
        raise LanternaInputError(where, str(err)) from None
    preferred = [str(f).lower() for f in info.get("preferredFormats", [])]
    fmt = next((f for f in preferred if f in FORMATS), "jpg")
    return ImageInfo(service.rstrip("/"), width, height, fmt)


def fetch_full(info: ImageInfo, where: str) -> FullImage:
    """Download ``full/max`` of a checked service (at most the bound its size allows)."""
    url = f"{info.service}/full/max/0/default.{info.fmt}"
    bound = info.width * info.height * BYTES_PER_PIXEL + SLACK_BYTES
    try:
        data = fetch(url, "an image", max_bytes=bound, accept="image/*")
    except LanternaInputError as err:
        raise LanternaInputError(where, str(err)) from None
    return FullImage(data, info.fmt, info.width, info.height, url)
