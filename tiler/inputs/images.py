"""Load an image file as 8-bit sRGB, with one-line errors."""

from __future__ import annotations

from pathlib import Path

import pyvips

from lanterna.errors import LanternaInputError
from lanterna.tiler.fileio import check_regular_file
from lanterna.tiler.limits import check_pixels


def load_rgb_image(path: Path) -> pyvips.Image:
    """Load an image file as 8-bit sRGB without alpha, with a clear error if it can't be read."""
    check_regular_file(path, "an image")
    try:
        img = pyvips.Image.new_from_file(str(path), access="sequential")
        check_pixels(path, img.width, img.height)
        if img.hasalpha():
            img = img.flatten(background=[0, 0, 0])
        if img.interpretation not in ("srgb", "b-w") or img.format != "uchar":
            img = img.colourspace("srgb").cast("uchar")
        if img.bands == 1:
            img = img.bandjoin([img, img])
        img = img.copy_memory()
    except pyvips.Error as err:
        first = str(err).strip().splitlines()[0] if str(err).strip() else "unreadable image"
        raise LanternaInputError(path, f"cannot read image ({first})") from None
    return img.copy(interpretation="srgb")
