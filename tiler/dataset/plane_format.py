"""Choose each plane group's tile format by its source (``--plane-format``, docs/dataset-format.md).

``auto`` (the default) measures candidates on a sample of the group's level-0 tiles — up to
:data:`SAMPLE_TILES` × :data:`SAMPLE_TILES` tiles around the centre, each encoded as the pyramid
would, so a big image does not pay several full encodes — and keeps the smallest that is
within the bound:

- a **lossless source** (8-bit PTM, HSH ``.rti``, fitted planes, PNG/TIFF maps): PNG or lossless
  WebP, whichever is smaller (both exact);
- a **lossy source** (JPEG PTM streams, a Relight folder's JPEG planes, JPEG maps): also JPEG at
  the lowest quality of :data:`JPEG_QUALITIES` within the bound and WebP near-lossless at each
  level within it. The error is measured against the source decode (the 8-bit values the
  reader produced): at most :data:`ERROR_RMS` code values RMS, no more than
  :data:`ERROR_OVER_SHARE` of the values off by more than :data:`ERROR_TOLERANCE`, none off by
  more than :data:`ERROR_MAX`.

``png``, ``webp`` (lossless) and ``jpg[:Q]`` force one format for every plane group.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt
import pyvips

from lanterna.errors import LanternaInputError
from lanterna.tiler.formats.planes import PlaneGroup
from lanterna.tiler.formats.strip_tiff import BandImage
from lanterna.tiler.iiif.encoding import (
    NEAR_LOSSLESS_LEVELS,
    PNG,
    WEBP,
    TileFormat,
    encode,
)
from lanterna.tiler.iiif.pyramid import vips_from_array

#: The bound on a lossy source's re-encoding error, in code values of the source decode: this
#: RMS over the sample ...
ERROR_RMS = 1.5
#: ... at most this share of the values further than ERROR_TOLERANCE (the pixel tests' 2/255)
#: from the source's (a share, not a maximum: re-encoding a Q90 JPEG at Q90 moves one value in
#: 10⁵ by 3–4 and the rest by 0–1, RMS 0.03; a maximum of 2 would refuse it for near-lossless
#: WebP at twice the bytes and 30× the RMS) ...
ERROR_TOLERANCE = 2
ERROR_OVER_SHARE = 0.001
#: ... and none further than this.
ERROR_MAX = 8
#: JPEG qualities tried for lossy sources, lowest first (the first within the bound is kept).
JPEG_QUALITIES = (75, 85, 90, 95, 98, 100)
#: The sample: up to this many level-0 tiles across and down, around the image's centre.
SAMPLE_TILES = 2
#: What ``--plane-format`` accepts.
USAGE = "--plane-format wants auto, png, webp or jpg[:Q] with Q in 1-100"


@dataclass(frozen=True)
class PlaneFormat:
    """The plane format asked for: ``auto``, or one format for every group (``fixed``)."""

    fixed: TileFormat | None = None

    @property
    def auto(self) -> bool:
        return self.fixed is None


AUTO = PlaneFormat()


def parse_plane_format(text: str) -> PlaneFormat:
    """Parse ``auto``, ``png``, ``webp``, ``jpg`` or ``jpg:Q``; anything else: a one-line error."""
    name, sep, quality = text.strip().lower().partition(":")
    if name == "auto" and not sep:
        return AUTO
    if name in ("png", "webp") and not sep:
        return PlaneFormat(TileFormat(name))
    if name in ("jpg", "jpeg") and (not sep or quality.isdigit() and 1 <= int(quality) <= 100):
        return PlaneFormat(TileFormat("jpg", int(quality) if sep else None))
    raise LanternaInputError(None, f"{USAGE}, got {text!r}")


@dataclass(frozen=True)
class Choice:
    """A format measured on the sample: its bytes and error against the source decode."""

    format: TileFormat
    bytes: int
    rms: float
    max: int
    #: The share of values off by more than ERROR_TOLERANCE.
    over: float = 0.0

    def within_bound(self) -> bool:
        return (self.rms <= ERROR_RMS and self.over <= ERROR_OVER_SHARE
                and self.max <= ERROR_MAX)


def choose_format(group: PlaneGroup, spec: PlaneFormat = AUTO, *, tile_size: int = 256
                  ) -> TileFormat:
    """The tile format of ``group``: ``spec``'s fixed format, or the ``auto`` choice."""
    if spec.fixed is not None:
        return spec.fixed
    within = [c for c in measure(group, tile_size=tile_size) if c.within_bound()]
    return min(within, key=lambda c: c.bytes).format


def candidates(lossy: bool) -> list[TileFormat]:
    """The formats ``auto`` measures for a lossy or a lossless source (exact ones last)."""
    exact = [WEBP, PNG]
    if not lossy:
        return exact
    return ([TileFormat("jpg", q) for q in JPEG_QUALITIES]
            + [TileFormat("webp", level) for level in NEAR_LOSSLESS_LEVELS] + exact)


def measure(group: PlaneGroup, *, tile_size: int = 256,
            formats: list[TileFormat] | None = None) -> list[Choice]:
    """Encode the sample tiles of ``group`` in each format (default :func:`candidates`).

    Each format's settings are tried from the most compressing (lowest JPEG quality, lowest
    near-lossless level) up, and stop at the first within the bound: a higher one would only be
    bigger. Exact formats are not decoded back: their error is 0.
    """
    tiles = sample_tiles(group, tile_size)
    out: list[Choice] = []
    done: set[str] = set()  # formats that have a setting within the bound already
    for fmt in formats if formats is not None else candidates(group.lossy):
        if fmt.ext in done:
            continue
        size, sq, top, count, over = 0, 0.0, 0, 0, 0
        for tile in tiles:
            data = encode(vips_from_array(tile), fmt)
            size += len(data)
            if not fmt.lossless:
                err = decode(data, tile.ndim).astype(np.int16) - tile
                size_err = np.abs(err)
                sq += float(np.square(err, dtype=np.float64).sum())
                top = max(top, int(size_err.max()))
                over += int(np.count_nonzero(size_err > ERROR_TOLERANCE))
                count += err.size
        choice = Choice(fmt, size, (sq / count) ** 0.5 if count else 0.0, top,
                        over / count if count else 0.0)
        if not fmt.lossless and choice.within_bound():
            done.add(fmt.ext)
        out.append(choice)
    return out


def sample_tiles(group: PlaneGroup, tile_size: int) -> list[npt.NDArray[np.uint8]]:
    """Up to ``SAMPLE_TILES``² level-0 tiles around the centre, on the pyramid's tile grid."""
    h, w = group.data.shape[:2]
    picks = []
    for size in (w, h):
        count = -(-size // tile_size)
        first = max(0, (count - SAMPLE_TILES) // 2)
        picks.append(range(first, min(count, first + SAMPLE_TILES)))
    out = []
    for ty in picks[1]:
        for tx in picks[0]:
            x0, y0 = tx * tile_size, ty * tile_size
            x1, y1 = min(w, x0 + tile_size), min(h, y0 + tile_size)
            out.append(_region(group, x0, y0, x1, y1))
    return out


def _region(group: PlaneGroup, x0: int, y0: int, x1: int, y1: int) -> npt.NDArray[np.uint8]:
    data = group.data
    if isinstance(data, BandImage):
        crop = data.vips().crop(x0, y0, x1 - x0, y1 - y0)
        array: npt.NDArray[np.uint8] = np.asarray(crop, dtype=np.uint8)
        return array.reshape((y1 - y0, x1 - x0) + data.shape[2:])
    return np.ascontiguousarray(data[y0:y1, x0:x1])


def decode(data: bytes, ndim: int) -> npt.NDArray[np.uint8]:
    """Decode an encoded tile to ``ndim`` dimensions (WebP gives 3 bands for a grey image)."""
    image = pyvips.Image.new_from_buffer(data, "")
    array: npt.NDArray[np.uint8] = np.asarray(image, dtype=np.uint8)
    if ndim == 2:
        return array[..., 0] if array.ndim == 3 else array
    return array
