"""Parse IIIF Image API 3 image requests: pure, no Flask and no pixels.

``parse_image_request`` turns the four path segments ``{region}/{size}/{rotation}/{quality}.
{format}`` and the image size into an :class:`ImageRequest` with integer pixel geometry, or
raises :class:`RequestError` with the status the spec asks for: 400 for bad syntax, a zero-size
or out-of-bounds region, upscaling without ``^``, a size over the limits or over what the format's
encoder can write (:data:`ENCODER_MAX_SIDE`); 501 for a valid request of a feature this server
does not implement (arbitrary rotation, upscaling when it is off, formats it cannot write).
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import TypeVar

#: Output formats and their media types (``jpg`` is required; the others are extras).
FORMATS = {"jpg": "image/jpeg", "png": "image/png", "webp": "image/webp", "tif": "image/tiff"}
#: Formats the spec names that this server does not write: a valid request, so 501.
KNOWN_FORMATS = ("gif", "jp2", "pdf")
#: The largest width or height each output format's encoder writes (None: no limit that any
#: request can reach), measured with libvips 8.18: libwebp refuses 16384 ("image too large"),
#: libjpeg-turbo 65501 ("Maximum supported image dimension is 65500 pixels"); PNG and TIFF were
#: written at 10,000,001 px. ``tests/python/server/test_image_api.py`` checks each value.
ENCODER_MAX_SIDE: dict[str, int | None] = {"jpg": 65500, "png": None, "webp": 16383, "tif": None}
#: The largest side every format served can be written at (WebP's), and so the largest
#: ``maxWidth``/``maxHeight`` the server publishes: ``max`` must be servable in every format.
MAX_SIDE = min(side for side in ENCODER_MAX_SIDE.values() if side is not None)
QUALITIES = ("default", "color", "gray", "bitonal")
_INT = r"(\d{1,9})"
_NUM = r"(\d{1,9}(?:\.\d*)?|\.\d+)"
_XYWH = re.compile(rf"^{_INT},{_INT},{_INT},{_INT}$")
_PCT_XYWH = re.compile(rf"^pct:{_NUM},{_NUM},{_NUM},{_NUM}$")
_SIZE = re.compile(rf"^(\^)?(?:(max)|pct:{_NUM}|(!)?{_INT}?,{_INT}?)$")
_ROTATION = re.compile(rf"^(!)?{_NUM}$")
_QUALITY_FORMAT = re.compile(r"^([a-z]+)\.([a-z0-9]+)$")
_T = TypeVar("_T")


class RequestError(Exception):
    """A request the server refuses, with its HTTP status (400, 404 or 501) and a short reason."""

    def __init__(self, status: int, message: str) -> None:
        super().__init__(message)
        self.status = status
        self.message = message


@dataclass(frozen=True)
class Limits:
    """Server limits on output images, as published in info.json.

    Attributes
    ----------
    max_width, max_height:
        Largest output width and height in pixels (``maxWidth``/``maxHeight``).
    max_area:
        Largest output area in pixels (``maxArea``).
    upscaling:
        Whether ``^`` sizes (upscaling) are served; without it they give 501.
    """

    max_width: int = MAX_SIDE
    max_height: int = MAX_SIDE
    max_area: int = 16 * 1024 * 1024
    upscaling: bool = False

    def encodable(self) -> Limits:
        """Return these limits with the sides lowered to :data:`MAX_SIDE` where above it."""
        return replace(self, max_width=min(self.max_width, MAX_SIDE),
                       max_height=min(self.max_height, MAX_SIDE))


@dataclass(frozen=True)
class ImageRequest:
    """One parsed image request.

    Attributes
    ----------
    x, y, w, h:
        The region in full-resolution pixels, cropped to the image.
    width, height:
        The output size before rotation.
    rotation:
        Clockwise rotation in degrees: 0, 90, 180 or 270 (applied after mirroring).
    mirror:
        Whether the image is mirrored left to right (the ``!`` prefix).
    quality, format:
        As requested (``quality`` in :data:`QUALITIES`, ``format`` in :data:`FORMATS`).
    """

    x: int
    y: int
    w: int
    h: int
    width: int
    height: int
    rotation: int
    mirror: bool
    quality: str
    format: str

    def canonical(self, image_width: int, image_height: int, limits: Limits) -> str:
        """Return ``region/size/rotation/quality.format`` in the Image API 3 canonical form."""
        full = (self.x, self.y, self.w, self.h) == (0, 0, image_width, image_height)
        region = "full" if full else f"{self.x},{self.y},{self.w},{self.h}"
        out = (self.width, self.height)
        if out == max_size(self.w, self.h, limits):
            size = "max"
        elif limits.upscaling and out == max_size(self.w, self.h, limits, upscale=True):
            size = "^max"
        else:
            up = self.width > self.w or self.height > self.h
            size = f"{'^' if up else ''}{self.width},{self.height}"
        rotation = f"{'!' if self.mirror else ''}{self.rotation}"
        return f"{region}/{size}/{rotation}/{self.quality}.{self.format}"


def max_size(rw: int, rh: int, limits: Limits, *, upscale: bool = False) -> tuple[int, int]:
    """Return the size ``max`` (or ``^max``) stands for on a ``rw × rh`` region.

    The largest size with the region's aspect ratio within ``limits``; never larger than the
    region unless ``upscale``.
    """
    scale = min(limits.max_width / rw, limits.max_height / rh,
                math.sqrt(limits.max_area / (rw * rh)))
    if not upscale:
        scale = min(scale, 1.0)
    if scale == 1.0:
        return rw, rh
    w, h = max(1, math.floor(rw * scale)), max(1, math.floor(rh * scale))
    while w * h > limits.max_area:  # the floor of a square root may overshoot by a pixel
        if w >= h:
            w -= 1
        else:
            h -= 1
    return w, h


def parse_region(text: str, width: int, height: int) -> tuple[int, int, int, int]:
    """Parse a region (``full``, ``square``, ``x,y,w,h``, ``pct:x,y,w,h``) into pixels.

    A region partly outside the image is cropped at its edge; a zero-size region or one wholly
    outside gives 400.
    """
    if text == "full":
        return 0, 0, width, height
    if text == "square":
        side = min(width, height)
        return (width - side) // 2, (height - side) // 2, side, side
    m = _XYWH.match(text)
    if m:
        x, y, w, h = (int(v) for v in m.groups())
    else:
        p = _PCT_XYWH.match(text)
        if not p:
            raise RequestError(400, f"bad region {text!r}")
        px, py, pw, ph = (float(v) for v in p.groups())
        if pw == 0 or ph == 0:
            raise RequestError(400, f"zero-size region {text!r}")
        x, y = round(px * width / 100), round(py * height / 100)
        w = max(1, round((px + pw) * width / 100) - x)
        h = max(1, round((py + ph) * height / 100) - y)
    if w == 0 or h == 0:
        raise RequestError(400, f"zero-size region {text!r}")
    if x >= width or y >= height:
        raise RequestError(400, f"region {text!r} is outside the {width}x{height} image")
    return x, y, min(w, width - x), min(h, height - y)


def parse_size(text: str, rw: int, rh: int, limits: Limits) -> tuple[int, int]:
    """Parse a size for a ``rw × rh`` region into the output ``(width, height)``.

    Without ``^`` a size larger than the region gives 400, including a ``!w,h`` box that the
    region would have to be enlarged to fill (what the official validator's ``size_noup`` test
    expects). With ``^`` and upscaling off: 501. Over the limits: 400.
    """
    m = _SIZE.match(text)
    if not m:
        raise RequestError(400, f"bad size {text!r}")
    caret, is_max, pct, confined, ws, hs = m.groups()
    if caret and not limits.upscaling:
        raise RequestError(501, "upscaling (^) is not supported")
    if is_max:
        return max_size(rw, rh, limits, upscale=bool(caret))
    if pct is not None:
        n = float(pct)
        w, h = round(rw * n / 100), round(rh * n / 100)
        if n == 0 or w == 0 or h == 0:
            raise RequestError(400, f"size {text!r} is less than one pixel")
    elif ws is None and hs is None or confined and (ws is None or hs is None):
        raise RequestError(400, f"bad size {text!r}")
    elif confined:
        bw, bh = int(ws), int(hs)
        if bw == 0 or bh == 0:
            raise RequestError(400, f"size {text!r} is less than one pixel")
        if bw * rh <= bh * rw:  # the width is the binding side
            w, h = bw, min(bh, max(1, round(rh * bw / rw)))
        else:
            w, h = min(bw, max(1, round(rw * bh / rh))), bh
    else:
        if ws is not None and int(ws) == 0 or hs is not None and int(hs) == 0:
            raise RequestError(400, f"size {text!r} is less than one pixel")
        w = int(ws) if ws is not None else max(1, round(rw * int(hs) / rh))
        h = int(hs) if hs is not None else max(1, round(rh * int(ws) / rw))
    if not caret and (w > rw or h > rh):
        raise RequestError(400, f"size {text!r} is larger than the {rw}x{rh} region; "
                           "upscaling needs ^")
    if w > limits.max_width or h > limits.max_height or w * h > limits.max_area:
        raise RequestError(400, f"size {w}x{h} exceeds the limits (maxWidth "
                           f"{limits.max_width}, maxHeight {limits.max_height}, maxArea "
                           f"{limits.max_area})")
    return w, h


def parse_rotation(text: str) -> tuple[int, bool]:
    """Parse a rotation into ``(degrees, mirror)``; only multiples of 90 are implemented."""
    m = _ROTATION.match(text)
    if not m:
        raise RequestError(400, f"bad rotation {text!r}")
    value = float(m.group(2))
    if value > 360:
        raise RequestError(400, f"rotation {text!r} is over 360")
    if value % 90 != 0:
        raise RequestError(501, "only rotations by multiples of 90 degrees are supported")
    return int(value) % 360, m.group(1) is not None


def parse_quality_format(text: str, formats: tuple[str, ...] = tuple(FORMATS)) -> tuple[str, str]:
    """Parse ``quality.format``; an unknown quality or format is 400, a known unsupported 501."""
    m = _QUALITY_FORMAT.match(text)
    if not m:
        raise RequestError(400, f"bad quality.format {text!r}")
    quality, fmt = m.groups()
    if quality not in QUALITIES:
        raise RequestError(400, f"unknown quality {quality!r}")
    if fmt not in formats:
        if fmt in KNOWN_FORMATS or fmt in FORMATS:
            raise RequestError(501, f"format {fmt!r} is not supported")
        raise RequestError(400, f"unknown format {fmt!r}")
    return quality, fmt


def parse_image_request(region: str, size: str, rotation: str, quality_format: str,
                        width: int, height: int, limits: Limits | None = None,
                        formats: tuple[str, ...] = tuple(FORMATS)) -> ImageRequest:
    """Parse the four parameter segments of an image request on a ``width × height`` image.

    Parameters
    ----------
    region, size, rotation, quality_format:
        The URL path segments, percent-decoded.
    width, height:
        The full image size.
    limits:
        Output limits (default :class:`Limits`).
    formats:
        The output formats served.

    Returns
    -------
    The request in pixels.

    Raises
    ------
    RequestError
        With status 400 or 501 (see the module docstring).
    """
    limits = limits or Limits()
    errors: list[RequestError] = []

    def attempt(parse: Callable[[], _T]) -> _T | None:
        try:
            return parse()
        except RequestError as err:
            errors.append(err)
            return None

    box = attempt(lambda: parse_region(region, width, height))
    out = attempt(lambda: parse_size(size, box[2], box[3], limits)) if box else None
    rot = attempt(lambda: parse_rotation(rotation))
    qf = attempt(lambda: parse_quality_format(quality_format, formats))
    if errors:  # a syntax error (400) wins over an unimplemented feature (501)
        raise min(errors, key=lambda err: err.status != 400)
    assert box is not None and out is not None and rot is not None and qf is not None
    side = ENCODER_MAX_SIDE.get(qf[1])
    if side is not None and max(out) > side:  # the limits allowed it: refuse before encoding
        raise RequestError(400, f"size {out[0]}x{out[1]} is too large for {qf[1]} (at most "
                           f"{side} pixels on a side)")
    return ImageRequest(*box, *out, *rot, *qf)
