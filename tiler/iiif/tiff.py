"""Write one image as a tiled pyramidal TIFF, the file the IIIF image server reads.

The file is a standard tiled multi-resolution TIFF as libvips ``tiffsave(pyramid=True)`` writes
it: full resolution in the first page (IFD), then each level half the size of the one before in
the following pages, until a level fits in one tile. IIPImage and Cantaloupe read it as is (see
``docs/serving.md``). Coefficient planes (``png`` images) are stored with lossless deflate, so the
data survives bit for bit; ``jpg`` images use JPEG Q90.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import pyvips

#: Tile size of the TIFF (IIPImage's convention; independent of the dataset's IIIF tile size).
TIFF_TILE = 256
JPEG_QUALITY = 90


def tiff_options(fmt: str) -> dict[str, Any]:
    """Return the ``tiffsave`` options for images of dataset format ``fmt`` (``png``/``jpg``).

    Parameters
    ----------
    fmt:
        ``"png"``: lossless deflate with the horizontal predictor. ``"jpg"``: JPEG Q90.

    Returns
    -------
    Keyword arguments for :meth:`pyvips.Image.tiffsave`.
    """
    common: dict[str, Any] = {"tile": True, "pyramid": True, "tile_width": TIFF_TILE,
                              "tile_height": TIFF_TILE, "bigtiff": False}
    if fmt == "png":
        return {**common, "compression": "deflate", "predictor": "horizontal"}
    if fmt == "jpg":
        return {**common, "compression": "jpeg", "Q": JPEG_QUALITY}
    raise ValueError(f"unknown image format {fmt!r} (expected png or jpg)")


def write_tiff(image: pyvips.Image, path: Path, *, fmt: str = "png") -> Path:
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
        The dataset image format: ``"png"`` (lossless) or ``"jpg"`` (JPEG Q90).

    Returns
    -------
    ``path``.
    """
    options = tiff_options(fmt)
    if image.format != "uchar":
        raise ValueError(f"write_tiff needs an 8-bit image, got {image.format}")
    if fmt == "jpg" and image.hasalpha():
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
