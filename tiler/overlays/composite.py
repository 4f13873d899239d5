"""Overlay level images: reading RGBA files, compositing patches, fitting a level's size.

Compositing is done in float64 on premultiplied colour, source-over in application order, and
rounded to 8-bit straight alpha once per level (``round(a·255)``, ``round(c/a·255)``).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import numpy.typing as npt
import pyvips

from lanterna.errors import LanternaInputError
from lanterna.tiler.fileio import check_regular_file
from lanterna.tiler.limits import check_pixels

from . import geometry as og

FloatImage = npt.NDArray[np.float64]


def load_rgba(path: Path) -> npt.NDArray[np.uint8]:
    """Read an image with an alpha channel as ``(H, W, 4)`` uint8 RGBA (grey + alpha expanded)."""
    check_regular_file(path, "an overlay image")
    try:
        img = pyvips.Image.new_from_file(str(path), access="sequential")
    except pyvips.Error as err:
        raise LanternaInputError(path, f"cannot read image ({_first(err)})") from None
    return rgba_of(img, path)


def decode_rgba(data: bytes, source: str | Path | None) -> npt.NDArray[np.uint8]:
    """:func:`load_rgba` of an encoded image in memory (an upload); errors name ``source``."""
    try:
        img = pyvips.Image.new_from_buffer(data, "", access="sequential")
    except pyvips.Error as err:
        raise LanternaInputError(source, f"cannot read image ({_first(err)})") from None
    return rgba_of(img, source)


def rgba_of(img: pyvips.Image, source: str | Path | None) -> npt.NDArray[np.uint8]:
    """Decode an opened image with alpha to ``(H, W, 4)`` uint8 RGBA; errors name ``source``."""
    try:
        check_pixels(source, img.width, img.height, "the overlay image")
        if not img.hasalpha():
            raise LanternaInputError(source, f"has no alpha channel ({img.bands} band(s)); "
                                     "overlay images must be RGBA")
        if img.interpretation not in ("srgb", "b-w") or img.format != "uchar":
            img = img.colourspace("srgb" if img.bands > 2 else "b-w").cast("uchar")
        if img.bands == 2:
            img = img[0].bandjoin([img[0], img[0], img[1]])
        if img.bands != 4:
            raise LanternaInputError(source, f"has {img.bands} bands; overlay images must be RGBA")
        array: npt.NDArray[np.uint8] = np.ascontiguousarray(img.numpy(), dtype=np.uint8)
    except pyvips.Error as err:
        raise LanternaInputError(source, f"cannot read image ({_first(err)})") from None
    return array


def _first(err: pyvips.Error) -> str:
    return str(err).strip().splitlines()[0] if str(err).strip() else "unreadable image"


def premultiply(rgba: npt.NDArray[np.uint8]) -> FloatImage:
    """Return premultiplied float colour and alpha in 0–1."""
    out = rgba.astype(np.float64) / 255.0
    out[..., :3] *= out[..., 3:4]
    return out


def unpremultiply(pre: FloatImage) -> npt.NDArray[np.uint8]:
    """Round premultiplied float RGBA to 8-bit straight alpha (colour 0 where fully transparent)."""
    alpha = np.clip(pre[..., 3:4], 0.0, 1.0)
    safe = np.where(alpha > 0, alpha, 1.0)
    colour = np.where(alpha > 0, np.clip(pre[..., :3] / safe, 0.0, 1.0), 0.0)
    out = np.concatenate([colour, alpha], axis=-1) * 255.0
    return np.rint(out).astype(np.uint8)


def resize_premultiplied(pre: FloatImage, width: int, height: int,
                         box: tuple[int, int, int, int] | None = None) -> FloatImage:
    """Resize premultiplied RGBA to exactly ``width`` × ``height`` (linear kernel, no ringing).

    ``box`` (left, top, width, height) returns only that part of the resized image: only it is
    computed, so a patch drawn much larger than the canvas costs its visible part alone.
    """
    h, w = pre.shape[:2]
    left, top, bw, bh = box if box is not None else (0, 0, width, height)
    if (w, h) == (width, height):
        return pre[top:top + bh, left:left + bw]
    img = pyvips.Image.new_from_array(np.ascontiguousarray(pre, dtype=np.float32))
    img = img.resize(width / w, vscale=height / h, kernel="linear")
    if (img.width, img.height) != (width, height):  # the rounding of the output size
        img = img.embed(0, 0, max(width, img.width), max(height, img.height), extend="copy")
        img = img.crop(0, 0, width, height)
    img = img.crop(left, top, bw, bh)
    out = np.asarray(img.numpy(), dtype=np.float64).reshape(bh, bw, 4)
    out[..., 3] = np.clip(out[..., 3], 0.0, 1.0)
    out[..., :3] = np.clip(out[..., :3], 0.0, out[..., 3:4])
    return out


def composite(level_w: int, level_h: int,
              items: list[tuple[npt.NDArray[np.uint8], og.Placement]]) -> npt.NDArray[np.uint8]:
    """Composite patches (RGBA, each with its placement) source-over, in list order."""
    acc = np.zeros((level_h, level_w, 4), np.float64)
    for rgba, placement in items:
        src = resize_premultiplied(premultiply(rgba), *placement.size, box=placement.source_box)
        cx0, cy0, cx1, cy1 = placement.clip
        dst = acc[cy0:cy1, cx0:cx1]
        dst *= 1.0 - src[..., 3:4]
        dst += src
    return unpremultiply(acc)


def drawn_box(rgba: npt.NDArray[np.uint8], level: int, width: int,
              height: int) -> list[int] | None:
    """The canvas rectangle ``[x, y, w, h]`` of a level image's drawn (not fully transparent)
    pixels, or None when nothing is drawn (the record's ``box``: docs/annotations.md)."""
    alpha = rgba[..., 3] > 0
    rows, cols = np.flatnonzero(alpha.any(axis=1)), np.flatnonzero(alpha.any(axis=0))
    if rows.size == 0:
        return None
    extent = (int(cols[0]), int(rows[0]), int(cols[-1]) + 1, int(rows[-1]) + 1)
    return list(og.canvas_box(extent, level, width, height))


def fit_level_image(rgba: npt.NDArray[np.uint8], level: int, width: int, height: int,
                    path: Path) -> npt.NDArray[np.uint8]:
    """Return a per-level image at its level's size.

    Accepted: the level's size; floor-halved sizes (one pixel short, padded transparent); or the
    full canvas size (downscaled by ``2^-L``). Anything else is an error naming both sizes.
    """
    lw, lh = og.level_size(width, height, level)
    h, w = rgba.shape[:2]
    if (w, h) == (lw, lh):
        return rgba
    if (w, h) == (width, height):
        return unpremultiply(resize_premultiplied(premultiply(rgba), lw, lh))
    if lw - 1 <= w <= lw and lh - 1 <= h <= lh:
        out = np.zeros((lh, lw, 4), np.uint8)
        out[:h, :w] = rgba
        return out
    raise LanternaInputError(path, f"is {w}x{h}; level {level} of the {width}x{height} canvas is "
                             f"{lw}x{lh}")
