"""Compute the image of an :class:`~lanterna.server.image_request.ImageRequest` from a pyramidal
TIFF (the IIIF image server's pixels; the HTTP side is :mod:`lanterna.server.image_api`).

Only the pyramid level just above the output resolution is decoded, and only the tiles under the
region: :func:`plan_read` (pure) picks the page and the pixel box, :func:`compute_image` crops it,
resizes it to the exact output size (lanczos3, downsampling by less than 2), mirrors, rotates,
applies the quality and :func:`encode` writes the format. Level ``k`` of a libvips pyramid is the
image box-filtered by ``2^k`` with odd edge pixels dropped, so full-resolution ``x`` maps to level
``x / 2^k`` exactly and tile requests on the pyramid's grid read no neighbouring pixels.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import pyvips

from .image_request import ImageRequest

JPEG_QUALITY = 90


@dataclass(frozen=True)
class ReadPlan:
    """The page of the TIFF to read and the box within it (level pixels)."""

    page: int
    x: int
    y: int
    w: int
    h: int


@lru_cache(maxsize=512)
def _levels_cached(path: str, _ino: int, _mtime_ns: int, _size: int) -> tuple[tuple[int, int], ...]:
    first = pyvips.Image.new_from_file(path, access="random", fail_on="error")
    pages = first.get("n-pages") if "n-pages" in first.get_fields() else 1
    levels = [(first.width, first.height)]
    for page in range(1, pages):
        img = pyvips.Image.new_from_file(path, page=page, access="random", fail_on="error")
        if img.width > levels[-1][0] or img.height > levels[-1][1]:
            break  # not a reduced-resolution level: stop at the pyramid
        levels.append((img.width, img.height))
    return tuple(levels)


def tiff_levels(path: Path) -> tuple[tuple[int, int], ...]:
    """Return ``(width, height)`` of every pyramid level (page) of the TIFF at ``path``.

    Cached by file identity (inode, mtime, size), so a replaced file is read again.
    """
    st = path.stat()
    return _levels_cached(str(path), st.st_ino, st.st_mtime_ns, st.st_size)


def plan_read(levels: tuple[tuple[int, int], ...], req: ImageRequest) -> ReadPlan:
    """Pick the smallest level at least as detailed as the output, and the box to read in it.

    Level ``k`` is used if the region there has more than ``size - 1`` pixels in both directions:
    the level is never enlarged by more than the one pixel that rounding a size up adds (the
    edge tiles of a pyramid, ``ceil(w / 2^k)`` wide, still come from level ``k``).
    """

    def detailed_enough(page: int) -> bool:
        f = 2**page
        return bool(req.w / f > req.width - 1 and req.h / f > req.height - 1)

    page = 0
    while page + 1 < len(levels) and detailed_enough(page + 1):
        page += 1
    f = 2**page
    lw, lh = levels[page]
    x0, y0 = min(lw - 1, math.floor(req.x / f)), min(lh - 1, math.floor(req.y / f))
    x1 = max(x0 + 1, min(lw, math.ceil((req.x + req.w) / f)))
    y1 = max(y0 + 1, min(lh, math.ceil((req.y + req.h) / f)))
    return ReadPlan(page, x0, y0, x1 - x0, y1 - y0)


def compute_image(path: Path, req: ImageRequest, plan: ReadPlan) -> pyvips.Image:
    """Return the output image of ``req`` (before encoding), reading ``plan`` from ``path``."""
    level = pyvips.Image.new_from_file(str(path), page=plan.page, access="random",
                                       fail_on="error", revalidate=True)
    img = level.crop(plan.x, plan.y, plan.w, plan.h)
    if (plan.w, plan.h) != (req.width, req.height):
        img = img.resize(req.width / plan.w, vscale=req.height / plan.h)
        if (img.width, img.height) != (req.width, req.height):  # rounding in resize: fix up
            img = img.gravity("north-west", req.width, req.height, extend="copy")
    if req.mirror:
        img = img.fliphor()
    if req.rotation == 90:
        img = img.rot90()
    elif req.rotation == 180:
        img = img.rot180()
    elif req.rotation == 270:
        img = img.rot270()
    return apply_quality(img, req.quality)


def apply_quality(img: pyvips.Image, quality: str) -> pyvips.Image:
    """Apply a IIIF quality: ``default`` as stored, ``color``, ``gray`` or ``bitonal``."""
    if quality == "color" and img.bands < 3:
        return img.colourspace("srgb")
    if quality in ("gray", "bitonal") and img.bands >= 3:
        img = img.colourspace("b-w")
    if quality == "bitonal":
        alpha = img[img.bands - 1] if img.hasalpha() else None
        img = img[0] > 128
        return img.bandjoin(alpha) if alpha is not None else img
    return img


def encode(img: pyvips.Image, fmt: str, *, lossless: bool) -> bytes:
    """Encode ``img`` as ``fmt`` (jpg, png, webp, tif); ``lossless`` picks lossless WebP."""
    if img.format != "uchar":
        img = img.cast("uchar")
    if fmt == "jpg":
        if img.hasalpha():
            img = img.flatten(background=[255] * (img.bands - 1))
        data = img.jpegsave_buffer(Q=JPEG_QUALITY, keep="none")
    elif fmt == "png":
        data = img.pngsave_buffer(compression=3, keep="none")
    elif fmt == "webp":
        data = img.webpsave_buffer(Q=JPEG_QUALITY, lossless=lossless, keep="none")
    elif fmt == "tif":
        data = img.tiffsave_buffer(compression="deflate", predictor="horizontal", keep="none")
    else:
        raise ValueError(f"cannot encode {fmt!r}")
    return bytes(data)
