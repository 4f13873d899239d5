"""Load shape and material maps and single-band images as 8-bit arrays ready for tiling.

- :func:`load_normal_map`: RGB normal map (8- or 16-bit), OpenGL or DirectX convention, checked
  for plausibility, re-normalised and encoded ``round((n + 1)/2·255)`` in the OpenGL convention
  (x right, y up, z toward the viewer; DirectX stores y down, so its green channel is flipped).
- :func:`load_color_map`: kd/ks maps and other RGB images, grey expanded to RGB.
- :func:`load_scalar_map`, :func:`load_band`: gloss maps, 8-bit depth maps and multispectral
  bands as one grey channel.
- :func:`load_depth_map`: depth (also float) stretched min..max to 0–255, with the range returned.
- :func:`is_lossy_file`: whether a map's file is a lossy (JPEG) encoding, which lets its planes
  be stored lossy within a bound (``--plane-format auto``).

16-bit samples become 8-bit by rounding ``v·255/65535``. Alpha is dropped. Pixel values are
taken as stored: no ICC or colour-space conversion. Files are decoded from memory with libvips
(whose load cache is keyed by file name, so a file rewritten in place is never served stale).
Every problem raises :class:`~lanterna.errors.LanternaInputError` with a one-line message.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import numpy.typing as npt
import pyvips

from lanterna.errors import LanternaInputError
from lanterna.tiler.fileio import read_input
from lanterna.tiler.limits import check_pixels

NORMAL_CONVENTIONS = ("opengl", "directx")
#: File suffixes of lossy encodings (a WebP may be either, so it counts as lossless).
LOSSY_SUFFIXES = (".jpg", ".jpeg")
_DTYPES = {"uchar": np.uint8, "ushort": np.uint16, "float": np.float32, "double": np.float64}
#: A decoded normal counts as plausible when its length is within this range.
_UNIT_RANGE = (0.6, 1.4)
#: 8-bit pixels this close to unit length are kept byte for byte (√3/255 ≈ 0.0068 is the
#: largest length error 8-bit rounding can cause), so re-encoding never drifts a valid map.
_KEEP_8BIT = 0.01
#: Shorter decoded vectors carry no direction (8-bit grey 128 is 0.0068 long); they become flat.
_SHORT = 0.05


def is_lossy_file(path: str | Path) -> bool:
    """True when ``path`` is a JPEG file (by its suffix): its pixels are a lossy decode."""
    return Path(path).suffix.lower() in LOSSY_SUFFIXES


def _read(path: str | Path, *, allow_float: bool = False,
          data: bytes | None = None) -> npt.NDArray[np.generic]:
    """Decode ``path`` (or ``data``, the file's bytes fetched from ``path``, a URL) to
    ``(H, W, bands)`` uint8/uint16 (or float), alpha dropped."""
    src = path if data is not None else Path(path)
    if data is None:
        data = read_input(Path(src), "an image")
    try:
        image = pyvips.Image.new_from_buffer(data, "", fail_on="warning")
        if image.interpretation == "cmyk":
            raise LanternaInputError(src, "CMYK images are not supported; convert to RGB")
        fmt = image.format
        if fmt not in _DTYPES or (fmt in ("float", "double") and not allow_float):
            raise LanternaInputError(src, f"unsupported sample format {fmt}; expected 8- or "
                                     "16-bit integer samples")
        bands, width, height = image.bands, image.width, image.height
        check_pixels(src, width, height)
        pixels = image.write_to_memory()
    except pyvips.Error as exc:
        reason = " ".join(str(exc.message or exc).split())[:80]
        raise LanternaInputError(src, f"cannot read image ({reason})") from None
    array = np.frombuffer(pixels, dtype=_DTYPES[fmt]).reshape(height, width, bands)
    if bands in (2, 4):
        array = array[..., : bands - 1]
    return array


def _to_unit(array: npt.NDArray[np.generic]) -> npt.NDArray[np.float64]:
    """Integer samples to 0–1."""
    top = 65535.0 if array.dtype == np.uint16 else 255.0
    out: npt.NDArray[np.float64] = array.astype(np.float64) / top
    return out


def _to_bytes(unit: npt.NDArray[np.floating]) -> npt.NDArray[np.uint8]:
    out: npt.NDArray[np.uint8] = np.clip(np.rint(unit * 255.0), 0, 255).astype(np.uint8)
    return out


def _to_8bit(array: npt.NDArray[np.generic]) -> npt.NDArray[np.uint8]:
    if array.dtype == np.uint8:
        return np.ascontiguousarray(array, dtype=np.uint8)
    return _to_bytes(_to_unit(array))


def load_normal_map(path: str | Path, *, convention: str = "opengl",
                    data: bytes | None = None) -> npt.NDArray[np.uint8]:
    """Load a normal map and return it as ``(H, W, 3)`` uint8 in the OpenGL convention.

    ``data``: the encoded file already read (fetched from ``path``, then a URL naming errors).

    Each pixel decodes as ``n = 2·v − 1`` (``v`` in 0–1, from 8 or 16 bits), the green channel
    is negated for ``convention="directx"``, and ``n`` is re-normalised before encoding
    ``round((n/‖n‖ + 1)/2·255)``; 8-bit pixels already unit length to within 8-bit rounding
    (±0.01) keep their bytes (green flipped for DirectX). Pixels that are 0 in every channel
    are taken as masked background: they are excluded from the checks and stay 0. Vectors
    shorter than 0.05 (grey pixels, no direction) become ``(0, 0, 1)``.

    Raises
    ------
    LanternaInputError
        If the file can't be read, is not 3-band (RGB, optional alpha), or does not look like a
        normal map: most pixels far from unit length (e.g. a grey or white image) or z below 0
        on average (e.g. a photograph or an inverted map).
    """
    if convention not in NORMAL_CONVENTIONS:
        raise LanternaInputError(path, f"unknown normal-map convention {convention!r}; "
                                 "expected opengl or directx")
    raw = _read(path, data=data)
    if raw.shape[2] != 3:
        raise LanternaInputError(path, f"normal map has {raw.shape[2]} colour band(s); "
                                 "expected 3 (RGB)")
    n = _to_unit(raw) * 2.0 - 1.0
    if convention == "directx":
        n[..., 1] = -n[..., 1]
    masked = ~raw.any(axis=-1)
    if masked.all():
        raise LanternaInputError(path, "image is entirely black; not a normal map")
    length = np.linalg.norm(n, axis=-1)
    lo, hi = _UNIT_RANGE
    live = length[~masked]
    if ((live < lo) | (live > hi)).mean() > 0.5:
        what = ("most pixels decode to near-zero vectors (a grey image?)" if (live < lo).mean()
                > 0.5 else "most pixels decode to vectors far from unit length")
        raise LanternaInputError(path, f"{what}; not a normal map")
    unit = np.where(length[..., None] >= _SHORT, n / np.maximum(length, _SHORT)[..., None],
                    (0.0, 0.0, 1.0))
    if unit[..., 2][~masked].mean() < 0.0:
        raise LanternaInputError(path, "the blue (z) channel is below 0.5 on average; not a "
                                 "normal map (z must point toward the viewer)")
    out = _to_bytes((unit + 1.0) * 0.5)
    if raw.dtype == np.uint8:
        keep = np.abs(length - 1.0) <= _KEEP_8BIT
        same = np.array(raw, dtype=np.uint8)
        if convention == "directx":
            same[..., 1] = 255 - same[..., 1]
        out[keep] = same[keep]
    out[masked] = 0
    return out


def load_color_map(path: str | Path, *, data: bytes | None = None) -> npt.NDArray[np.uint8]:
    """Load an RGB (or grey) image as ``(H, W, 3)`` uint8; 16-bit samples are rounded to 8
    (``data``: the encoded file already read, as for :func:`load_normal_map`)."""
    raw = _read(path, data=data)
    if raw.shape[2] == 1:
        raw = np.repeat(raw, 3, axis=2)
    elif raw.shape[2] != 3:
        raise LanternaInputError(path, f"image has {raw.shape[2]} colour bands; expected grey "
                                 "or RGB")
    return _to_8bit(raw)


def _grey(path: str | Path, raw: npt.NDArray[np.generic], what: str) -> npt.NDArray[np.generic]:
    """Return the single channel of ``raw``; an RGB image is accepted when R = G = B."""
    bands = raw.shape[2]
    if bands == 3 and (raw[..., 0] == raw[..., 1]).all() and (raw[..., 0] == raw[..., 2]).all():
        return raw[..., 0]
    if bands != 1:
        detail = "different colour bands" if bands == 3 else "bands"
        raise LanternaInputError(path, f"{what} has {bands} {detail}; expected a single-band "
                                 "(grey) image")
    return raw[..., 0]


def load_scalar_map(path: str | Path) -> npt.NDArray[np.uint8]:
    """Load a gloss or depth map as ``(H, W)`` uint8 (16-bit rounded to 8, no stretching)."""
    return _to_8bit(_grey(path, _read(path), "map"))


def load_band(path: str | Path) -> npt.NDArray[np.uint8]:
    """Load one multispectral band as ``(H, W)`` uint8 (16-bit rounded to 8, no stretching)."""
    return _to_8bit(_grey(path, _read(path), "band"))


def load_depth_map(path: str | Path) -> tuple[npt.NDArray[np.uint8], tuple[float, float]]:
    """Load a depth map (8/16-bit or float) stretched to 0–255 over its finite min..max.

    Returns
    -------
    data, (low, high)
        ``(H, W)`` uint8 with ``round((d − low)/(high − low)·255)`` (0 where the depth is not
        finite, and everywhere if the map is constant), and the range in the file's own units.
    """
    d = _grey(path, _read(path, allow_float=True), "depth map").astype(np.float64)
    finite = np.isfinite(d)
    if not finite.any():
        raise LanternaInputError(path, "depth map has no finite value")
    low, high = float(d[finite].min()), float(d[finite].max())
    span = high - low
    scaled = np.where(finite, (np.where(finite, d, low) - low) / (span if span > 0 else 1.0),
                      0.0)
    return _to_bytes(scaled), (low, high)
