"""Write one image as a tiled pyramidal TIFF, the file the IIIF image server reads.

The file is a standard tiled multi-resolution TIFF as libvips ``tiffsave(pyramid=True)`` writes
it: full resolution in the first page (IFD), then each level half the size of the one before in
the following pages, until a level fits in one tile. IIPImage and Cantaloupe read it as is (see
``docs/serving.md``). Images whose tiles are lossless or near-lossless (``png``, ``webp``) are
stored with lossless deflate, so the data survives bit for bit (IIPImage and Cantaloupe do not
all read WebP-compressed TIFF); ``jpg`` images use JPEG at the tiles' quality (default Q90).
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import pyvips

from .encoding import TileFormat, tile_format

#: Tile size of the TIFF (IIPImage's convention; independent of the dataset's IIIF tile size).
TIFF_TILE = 256


def tiff_options(fmt: str | TileFormat) -> dict[str, Any]:
    """Return the ``tiffsave`` options for images of dataset format ``fmt``.

    Parameters
    ----------
    fmt:
        ``"png"``, ``"webp"``: lossless deflate with the horizontal predictor. ``"jpg"``: JPEG
        at the format's quality (Q90 by default).

    Returns
    -------
    Keyword arguments for :meth:`pyvips.Image.tiffsave`.
    """
    common: dict[str, Any] = {"tile": True, "pyramid": True, "tile_width": TIFF_TILE,
                              "tile_height": TIFF_TILE, "bigtiff": False}
    tf = tile_format(fmt)
    if tf.ext == "jpg":
        return {**common, "compression": "jpeg", "Q": tf.options()["Q"]}
    return {**common, "compression": "deflate", "predictor": "horizontal"}


def write_tiff(image: pyvips.Image, path: Path, *, fmt: str | TileFormat = "png") -> Path:
    """Write ``image`` as a tiled pyramidal TIFF at ``path``, atomically.

    The file is written under a temporary name beside ``path`` and renamed into place, so a
    reader never sees half a file.

    Parameters
    ----------
    image:
        An 8-bit image with 1–4 bands (alpha is flattened for ``jpg``, which cannot hold it).
    path:
        The ``.tif`` file to create (its folder must exist); an existing file is replaced.
    fmt:
        The dataset image format: ``"png"``/``"webp"`` (stored lossless) or ``"jpg"`` (JPEG).

    Returns
    -------
    ``path``.
    """
    options = tiff_options(fmt)
    if image.format != "uchar":
        raise ValueError(f"write_tiff needs an 8-bit image, got {image.format}")
    if tile_format(fmt).ext == "jpg" and image.hasalpha():
        image = image.flatten()
    # Files over 4 GB need BigTIFF, which older readers refuse; use it only when needed.
    options["bigtiff"] = image.width * image.height * image.bands * 4 // 3 > 3_900_000_000
    path = Path(path)
    part = path.with_name(f".{path.name}.part-{os.getpid()}.tif")
    try:
        image.tiffsave(str(part), **options)
        os.replace(part, path)
    finally:
        part.unlink(missing_ok=True)
    return path
