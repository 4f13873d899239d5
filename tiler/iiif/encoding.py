"""Tile encodings: the file format of an image's tiles and its settings, one table for all.

A :class:`TileFormat` is what a pyramid's tiles, ``sizes`` files and ``full/max`` are written
in (``docs/dataset-format.md``, "Tile formats"):

- ``png``: lossless (deflate level 3);
- ``webp``: lossless WebP, or near-lossless with a libwebp preprocessing level (``quality``
  40/60/80: values moved by a few code values where that saves bytes; 100 is lossless);
- ``jpg``: JPEG at ``quality`` (default 90), always 4:4:4 (a coefficient plane's second and
  third channels are data, not chroma to subsample).

Lossy WebP is not offered: it is always 4:2:0, which costs coefficient planes 5 code values
RMS at Q100 (measured in docs/dataset-format.md).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pyvips

#: JPEG quality when none is given (previews, plain images, ``jpg`` planes without ``:Q``).
JPEG_QUALITY = 90
#: libwebp effort (0–6) for WebP tiles: 1 is within 1 % of 4's bytes on coefficient planes at a
#: fraction of its time; 0 is faster still but 8 % bigger and turns near-lossless off.
WEBP_EFFORT = 1
#: libwebp's near-lossless levels (it rounds any other value down to one of these).
NEAR_LOSSLESS_LEVELS = (40, 60, 80)
#: File suffixes of the formats, the same as the IIIF format names.
FORMATS = ("png", "webp", "jpg")


@dataclass(frozen=True)
class TileFormat:
    """An image's tile format: ``ext`` (``png``, ``webp``, ``jpg``) and its ``quality``.

    ``quality`` is the JPEG Q for ``jpg``, the near-lossless level for ``webp`` (None: exactly
    lossless) and None for ``png``.
    """

    ext: str
    quality: int | None = None

    def __post_init__(self) -> None:
        if self.ext not in FORMATS:
            raise ValueError(f"unknown tile format {self.ext!r} (expected png, webp or jpg)")
        if self.ext == "png" and self.quality is not None:
            raise ValueError("png has no quality")
        if self.ext == "jpg" and self.quality is not None and not 1 <= self.quality <= 100:
            raise ValueError(f"JPEG quality must be 1-100, got {self.quality}")
        if self.ext == "webp" and self.quality not in (None, *NEAR_LOSSLESS_LEVELS):
            raise ValueError(f"WebP near-lossless level must be one of {NEAR_LOSSLESS_LEVELS}")

    @property
    def lossless(self) -> bool:
        """True when decoding a tile gives back exactly the pixels encoded."""
        return self.ext == "png" or (self.ext == "webp" and self.quality is None)

    def options(self) -> dict[str, Any]:
        """The libvips save options (``pngsave``/``webpsave``/``jpegsave``)."""
        return _OPTIONS[self.ext](self.quality)

    def dz_suffix(self) -> str:
        """The ``dzsave`` ``suffix``: the extension with the save options."""
        opts = ",".join(f"{k}={_vips_value(v)}" for k, v in self.options().items())
        return f".{self.ext}[{opts}]"

    def label(self) -> str:
        """``png``, ``webp``, ``webp:near60``, ``jpg:85``: how the docs and reports name it."""
        if self.quality is None:
            return self.ext if self.ext != "jpg" else f"jpg:{JPEG_QUALITY}"
        return f"webp:near{self.quality}" if self.ext == "webp" else f"{self.ext}:{self.quality}"


PNG = TileFormat("png")
WEBP = TileFormat("webp")
JPG = TileFormat("jpg")

def _png(quality: int | None) -> dict[str, Any]:
    return {"compression": 3}


def _webp(quality: int | None) -> dict[str, Any]:
    lossless: dict[str, Any] = {"lossless": True, "effort": WEBP_EFFORT}
    return lossless if quality is None else {**lossless, "near_lossless": True, "Q": quality}


def _jpg(quality: int | None) -> dict[str, Any]:
    return {"Q": JPEG_QUALITY if quality is None else quality, "subsample_mode": "off"}


#: Each format's libvips save options for a quality.
_OPTIONS: dict[str, Callable[[int | None], dict[str, Any]]] = {
    "png": _png, "webp": _webp, "jpg": _jpg}


def _vips_value(value: object) -> str:
    return ("true" if value else "false") if isinstance(value, bool) else str(value)


def tile_format(fmt: str | TileFormat) -> TileFormat:
    """``fmt`` as a :class:`TileFormat` (a plain name has its default settings)."""
    return fmt if isinstance(fmt, TileFormat) else TileFormat(fmt)


def encode(image: pyvips.Image, fmt: TileFormat) -> bytes:
    """Encode ``image`` in ``fmt`` (alpha flattened for JPEG) and return the file's bytes."""
    if fmt.ext == "jpg" and image.hasalpha():
        image = image.flatten()
    return bytes(image.write_to_buffer(f".{fmt.ext}", **fmt.options()))


def save(image: pyvips.Image, target: Path, fmt: TileFormat) -> None:
    """Write ``image`` to ``target`` in ``fmt`` (alpha flattened for JPEG)."""
    if fmt.ext == "jpg" and image.hasalpha():
        image = image.flatten()
    image.write_to_file(str(target), **fmt.options())
