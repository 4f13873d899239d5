"""Load a multi-light image collection (one photograph per light) as one float stack."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
import numpy.typing as npt
import pyvips

from .errors import LanternaInputError

#: Divisor turning each libvips band format into 0–1.
_FULL_SCALE = {"uchar": 255.0, "ushort": 65535.0}


def load_image(path: Path) -> npt.NDArray[np.float32]:
    """Return one image as ``(H, W, 3)`` float32 in 0–1, values as stored (no gamma change).

    JPEG, PNG and TIFF, 8 or 16 bit; grey images are repeated to RGB and alpha is dropped.
    Float TIFFs are taken as already in 0–1.
    """
    try:
        img = pyvips.Image.new_from_file(str(path), access="sequential")
        if img.hasalpha():
            img = img.extract_band(0, n=img.bands - 1)
        if img.bands == 1:
            img = img.bandjoin([img, img])
        elif img.bands > 3:
            img = img.extract_band(0, n=3)
        array = img.numpy()
    except pyvips.Error as err:
        first = str(err).strip().splitlines()[0] if str(err).strip() else "unreadable image"
        raise LanternaInputError(path, f"cannot read image ({first})") from None
    if img.bands != 3:
        raise LanternaInputError(path, f"expected an RGB or grey image, got {img.bands} bands")
    out: npt.NDArray[np.float32] = np.asarray(array, np.float32).reshape(img.height, img.width, 3)
    if img.format in _FULL_SCALE:
        return out / np.float32(_FULL_SCALE[img.format])
    if img.format in ("float", "double"):
        return out
    raise LanternaInputError(path, f"unsupported sample format {img.format} "
                             "(expected 8 or 16 bit, or float)")


def load_stack(files: Sequence[Path]) -> npt.NDArray[np.float32]:
    """Load the images of ``files`` as ``(N, H, W, 3)`` float32 in 0–1.

    Raises
    ------
    LanternaInputError
        Naming the file that cannot be read, or whose size differs from the first image's.
    """
    if not files:
        raise LanternaInputError(None, "no images to load")
    first = load_image(files[0])
    h, w = first.shape[:2]
    stack = np.empty((len(files), h, w, 3), np.float32)
    stack[0] = first
    for i, path in enumerate(files[1:], 1):
        img = load_image(path)
        if img.shape[:2] != (h, w):
            raise LanternaInputError(path, f"is {img.shape[1]}x{img.shape[0]}, but "
                                     f"{Path(files[0]).name} is {w}x{h}: all images of a "
                                     "collection must have the same size")
        stack[i] = img
    return stack
