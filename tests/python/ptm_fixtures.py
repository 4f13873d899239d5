"""Builders for small synthetic PTMs and an independent JPEG-PTM decoder for the tests.

The decoder here is written from rti-formats.md §1.4 separately from ``tiler/formats/ptm.py`` so
that the tests do not check the reader against itself.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import numpy.typing as npt
import pyvips

from lanterna.tiler.formats.ptm_model import Ptm
from tests.python.fixtures.ptm_writer import PtmPrediction

SCALE = np.array([0.5, 0.25, 1.5, 2.0, 3.0, 0.00390625], dtype=np.float32)
BIAS = np.array([160, 150, 128, 127, -5, 0], dtype=np.int32)


def random_ptm(colorspace: str, width: int = 13, height: int = 7, seed: int = 0) -> Ptm:
    """Return a PTM with random bytes (every byte distinct in position), rows top-down."""
    rng = np.random.default_rng(seed)
    if colorspace == "lrgb":
        coeffs = rng.integers(0, 256, (height, width, 6), dtype=np.uint8)
        rgb = rng.integers(0, 256, (height, width, 3), dtype=np.uint8)
        return Ptm("lrgb", coeffs, SCALE, BIAS, rgb)
    coeffs = rng.integers(0, 256, (height, width, 3, 6), dtype=np.uint8)
    return Ptm("rgb", coeffs, SCALE, BIAS)


def smooth_ptm(colorspace: str, width: int = 40, height: int = 24, seed: int = 0) -> Ptm:
    """Return a PTM whose planes are smooth ramps in 30–225 (JPEG-friendly), rows top-down."""
    rng = np.random.default_rng(seed)
    n = 9 if colorspace == "lrgb" else 18
    y, x = np.mgrid[0:height, 0:width].astype(np.float64)
    planes = []
    for _ in range(n):
        fx, fy, phase = rng.uniform(0.02, 0.12), rng.uniform(0.02, 0.12), rng.uniform(0, 6)
        planes.append(127.5 + 95 * np.sin(fx * x + fy * y + phase))
    stack = np.rint(np.stack(planes, axis=-1)).astype(np.uint8)
    if colorspace == "lrgb":
        return Ptm(
            "lrgb",
            np.ascontiguousarray(stack[..., :6]),
            SCALE,
            BIAS,
            np.ascontiguousarray(stack[..., 6:]),
        )
    coeffs = np.ascontiguousarray(stack.reshape(height, width, 3, 6))
    return Ptm("rgb", coeffs, SCALE, BIAS)


def jpeg_bytes(plane: npt.NDArray[np.uint8], quality: int = 100) -> bytes:
    """Encode an ``(H, W)`` uint8 array (JPEG raster order) as a grayscale JPEG."""
    h, w = plane.shape
    image = pyvips.Image.new_from_memory(np.ascontiguousarray(plane).tobytes(), w, h, 1, "uchar")
    data: bytes = image.jpegsave_buffer(Q=quality)
    return data


def jpeg_pixels(data: bytes) -> npt.NDArray[np.uint8]:
    """Decode a grayscale JPEG to ``(H, W)`` uint8."""
    image = pyvips.Image.new_from_buffer(data, "")
    assert image.bands == 1
    return np.ndarray(
        (image.height, image.width), dtype=np.uint8, buffer=image.write_to_memory()
    ).copy()


def reference_decode_jpeg_ptm(path: Path) -> npt.NDArray[np.uint8]:
    """Decode a JPEG PTM straight from rti-formats §1.4; return planes ``(n, H, W)`` top-down."""
    data = path.read_bytes()
    lines = data.split(b"\n", 14)
    fmt = lines[1].decode().strip()
    n = {"PTM_FORMAT_JPEG_LRGB": 9, "PTM_FORMAT_JPEG_RGB": 18}[fmt]
    w, h = int(lines[2]), int(lines[3])
    table = [[int(t) for t in lines[k].split()] for k in range(7, 14)]
    transform, _mx, _my, order, reference, sizes, sides = table
    payload = lines[14]
    starts = np.cumsum([0] + [s + q for s, q in zip(sizes, sides, strict=True)])
    out = np.zeros((n, h, w), dtype=np.uint8)  # JPEG raster order (bottom-up) while decoding
    for k in range(n):
        i = order.index(k)  # the plane decoded k-th
        stream = payload[starts[i] : starts[i] + sizes[i]]
        plane = jpeg_pixels(stream).astype(np.int64)
        r = reference[i]
        if r >= 0:
            ref = out[r].astype(np.int64)
            if transform[i] & 1:
                ref = 255 - ref
            plane = np.mod(ref + plane - 128, 256)
        side = payload[starts[i] + sizes[i] : starts[i + 1]]
        for j in range(0, len(side), 5):
            index = int.from_bytes(side[j : j + 4], "big")
            plane[index // w, index % w] = side[j + 4]
        out[i] = plane.astype(np.uint8)
    return out[:, ::-1]


def planes_of(ptm: Ptm) -> npt.NDArray[np.uint8]:
    """Return the PTM's planes in JPEG stream order, ``(n, H, W)``, rows top-down."""
    if ptm.colorspace == "lrgb":
        assert ptm.rgb is not None
        return np.concatenate([ptm.coefficients, ptm.rgb], axis=2).transpose(2, 0, 1)
    h, w = ptm.height, ptm.width
    planes: npt.NDArray[np.uint8] = ptm.coefficients.reshape(h, w, 18).transpose(2, 0, 1)
    return planes


def header_bytes(
    fmt: str,
    width: int | str,
    height: int | str,
    *,
    version: str = "PTM_1.2",
    scale: str = "0.5 0.25 1.5 2.0 3.0 0.00390625",
    bias: str = "160 150 128 127 -5 0",
) -> bytes:
    """Return the six common header lines."""
    return f"{version}\n{fmt}\n{width}\n{height}\n{scale}\n{bias}\n".encode()


def with_overflow(ptm: Ptm) -> Ptm:
    """Put extreme values at pixel (row 2, col 5) so predicted residuals must be clipped."""
    coeffs = ptm.coefficients.copy()
    rgb = None if ptm.rgb is None else ptm.rgb.copy()
    if ptm.colorspace == "lrgb":
        assert rgb is not None
        coeffs[2, 5, 0], coeffs[2, 5, 5] = 3, 3  # plane 0 predicted from inverted plane 5
        rgb[2, 5, 0], rgb[2, 5, 1] = 250, 4  # plane 6 predicted from plane 7
    else:
        coeffs[2, 5, 0, 1], coeffs[2, 5, 0, 0] = 250, 2  # plane 1 predicted from plane 0
        coeffs[2, 5, 1, 0], coeffs[2, 5, 0, 0] = 2, 2  # plane 6 predicted from inverted plane 0
    return Ptm(ptm.colorspace, coeffs, ptm.scale, ptm.bias, rgb)


LRGB_PREDICTION = PtmPrediction(
    order=[8, 4, 3, 2, 1, 7, 5, 0, 6],
    reference=[5, -1, -1, -1, -1, 1, 7, -1, 7],
    transform=[1, 0, 0, 0, 0, 1, 0, 0, 0],
)
RGB_PREDICTION = PtmPrediction(
    order=[0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 17, 16, 15, 14, 13, 12],
    reference=[-1, 0, 0, 1, -1, 4, 0, 6, 6, -1, -1, -1, 17, -1, -1, -1, -1, 0],
    transform=[0, 0, 1, 0, 0, 1, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0],
)
