"""A minimal DNG writer for the tests: a known linear RGB scene, mosaicked into a Bayer raw.

Written from the TIFF 6.0 and DNG 1.4 specifications (tag numbers and types in ``_tags``), not
from any RAW library, so that :mod:`lanterna.tiler.raw` is checked against an independent
encoder.  The file is little-endian TIFF with the raw CFA image in IFD 0 (``NewSubFileType``
0, as DNG allows), uncompressed 16-bit samples in one strip, an RGGB 2×2 pattern, and the
colour tags a DNG reader needs: ``ColorMatrix1`` (XYZ → camera) with
``CalibrationIlluminant1`` D65, ``AsShotNeutral``, ``BlackLevel`` and ``WhiteLevel``.

The camera here is chosen so the expected decode is known exactly: its native RGB *is*
linear sRGB (``ColorMatrix1`` = the XYZ → linear-sRGB matrix), and its raw response to a
scene colour ``s`` (linear sRGB, white = 1) is ``black + s · neutral · (white − black)``.
A decoder applying the camera white balance (multipliers ``1 / neutral``, the smallest
being 1 when ``max(neutral) == 1``), the file's levels and the colour matrix must then
return ``s`` itself, scaled to 0–65535.
"""

from __future__ import annotations

import struct
from fractions import Fraction
from pathlib import Path

import numpy as np
import numpy.typing as npt

#: XYZ (D65) → linear sRGB, IEC 61966-2-1; the inverse of the sRGB primaries matrix.
XYZ_TO_SRGB = np.array([[3.2404542, -1.5371385, -0.4985314],
                        [-0.9692660, 1.8760108, 0.0415560],
                        [0.0556434, -0.2040259, 1.0572252]])

BLACK = 512
WHITE = 15000
#: Camera raw response to scene white, per channel (green is the reference, as in cameras).
NEUTRAL = (0.5, 1.0, 0.8)

# TIFF field types
_BYTE, _ASCII, _SHORT, _LONG, _RATIONAL, _SRATIONAL = 1, 2, 3, 4, 5, 10
_FORMAT = {_BYTE: "B", _ASCII: "B", _SHORT: "H", _LONG: "I", _RATIONAL: "II",
           _SRATIONAL: "ii"}


def mosaic(rgb: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """Sample an ``(H, W, 3)`` image through an RGGB colour filter array → ``(H, W)``."""
    cfa = np.empty(rgb.shape[:2])
    cfa[0::2, 0::2] = rgb[0::2, 0::2, 0]  # R
    cfa[0::2, 1::2] = rgb[0::2, 1::2, 1]  # G
    cfa[1::2, 0::2] = rgb[1::2, 0::2, 1]  # G
    cfa[1::2, 1::2] = rgb[1::2, 1::2, 2]  # B
    return cfa


def scene_to_raw(scene: npt.NDArray[np.float64],
                 neutral: tuple[float, float, float] = NEUTRAL) -> npt.NDArray[np.uint16]:
    """Return the 16-bit CFA samples this camera records for a linear sRGB ``scene``."""
    camera = np.clip(scene * np.asarray(neutral), 0.0, 1.0)
    counts = BLACK + mosaic(camera) * (WHITE - BLACK)
    return np.round(counts).astype(np.uint16)


def _rationals(values: list[float], signed: bool) -> list[int]:
    """Flatten ``values`` into numerator/denominator pairs (denominator ≤ 10⁶)."""
    out: list[int] = []
    for v in values:
        f = Fraction(v).limit_denominator(1_000_000)
        if not signed and f < 0:
            raise ValueError("RATIONAL must be non-negative")
        out += [f.numerator, f.denominator]
    return out


def _tags(raw: npt.NDArray[np.uint16], orientation: int,
          neutral: tuple[float, float, float]) -> list[tuple[int, int, list[int]]]:
    """Return IFD 0's entries as ``(tag, type, values)``; StripOffsets is patched later."""
    h, w = raw.shape
    model = list(b"Lanterna Synthetic DNG\0")
    return [
        (254, _LONG, [0]),                        # NewSubFileType: main image
        (256, _LONG, [w]),                        # ImageWidth
        (257, _LONG, [h]),                        # ImageLength
        (258, _SHORT, [16]),                      # BitsPerSample
        (259, _SHORT, [1]),                       # Compression: none
        (262, _SHORT, [32803]),                   # PhotometricInterpretation: CFA
        (271, _ASCII, list(b"Lanterna\0")),       # Make
        (272, _ASCII, list(b"Synthetic\0")),      # Model
        (273, _LONG, [0]),                        # StripOffsets (patched)
        (274, _SHORT, [orientation]),             # Orientation
        (277, _SHORT, [1]),                       # SamplesPerPixel
        (278, _LONG, [h]),                        # RowsPerStrip: one strip
        (279, _LONG, [raw.nbytes]),               # StripByteCounts
        (284, _SHORT, [1]),                       # PlanarConfiguration: chunky
        (33421, _SHORT, [2, 2]),                  # CFARepeatPatternDim
        (33422, _BYTE, [0, 1, 1, 2]),             # CFAPattern: R G / G B
        (50706, _BYTE, [1, 4, 0, 0]),             # DNGVersion 1.4
        (50707, _BYTE, [1, 1, 0, 0]),             # DNGBackwardVersion 1.1
        (50708, _ASCII, model),                   # UniqueCameraModel
        (50710, _BYTE, [0, 1, 2]),                # CFAPlaneColor: R, G, B
        (50711, _SHORT, [1]),                     # CFALayout: rectangular
        (50714, _LONG, [BLACK]),                  # BlackLevel (1×1 repeat)
        (50717, _LONG, [WHITE]),                  # WhiteLevel
        (50721, _SRATIONAL, _rationals(XYZ_TO_SRGB.ravel().tolist(), True)),  # ColorMatrix1
        (50728, _RATIONAL, _rationals(list(neutral), False)),  # AsShotNeutral
        (50778, _SHORT, [21]),                    # CalibrationIlluminant1: D65
    ]


def dng_bytes(raw: npt.NDArray[np.uint16], orientation: int = 1,
              neutral: tuple[float, float, float] = NEUTRAL) -> bytes:
    """Encode the CFA samples ``raw`` (``(H, W)`` uint16, RGGB) as a DNG file."""
    tags = sorted(_tags(raw, orientation, neutral))
    ifd_offset = 8
    ifd_size = 2 + 12 * len(tags) + 4
    extra = bytearray()  # values longer than 4 bytes, after the IFD
    extra_base = ifd_offset + ifd_size
    entries = bytearray()
    strip_entry = -1
    for tag, kind, values in tags:
        count = len(values) // 2 if kind in (_RATIONAL, _SRATIONAL) else len(values)
        data = struct.pack("<" + _FORMAT[kind][0] * len(values), *values)
        if tag == 273:
            strip_entry = len(entries)
        if len(data) <= 4:
            field = data.ljust(4, b"\0")
        else:
            if len(extra) % 2:
                extra += b"\0"  # values start on a word boundary
            field = struct.pack("<I", extra_base + len(extra))
            extra += data
        entries += struct.pack("<HHI", tag, kind, count) + field
    strip_offset = extra_base + len(extra) + (len(extra) % 2)
    entries[strip_entry + 8:strip_entry + 12] = struct.pack("<I", strip_offset)
    out = bytearray(b"II" + struct.pack("<HI", 42, ifd_offset))
    out += struct.pack("<H", len(tags)) + entries + struct.pack("<I", 0)
    out += extra + b"\0" * (len(extra) % 2)
    out += np.ascontiguousarray(raw, "<u2").tobytes()
    return bytes(out)


def write_dng(path: Path, scene: npt.NDArray[np.float64], orientation: int = 1,
              neutral: tuple[float, float, float] = NEUTRAL) -> Path:
    """Write the DNG this camera would record for ``scene`` (``(H, W, 3)`` linear sRGB)."""
    path.write_bytes(dng_bytes(scene_to_raw(scene, neutral), orientation, neutral))
    return path


def patch_scene(height: int = 48, width: int = 64) -> npt.NDArray[np.float64]:
    """Return a scene of four flat quadrants (see :data:`PATCHES`), linear sRGB."""
    scene = np.empty((height, width, 3))
    for (qy, qx), colour in PATCHES.items():
        scene[qy * height // 2:(qy + 1) * height // 2,
              qx * width // 2:(qx + 1) * width // 2] = colour
    return scene


#: Quadrant (row, column) → linear sRGB colour: grey 18 %, a warm colour, white, dark blue.
PATCHES: dict[tuple[int, int], tuple[float, float, float]] = {
    (0, 0): (0.18, 0.18, 0.18),
    (0, 1): (0.60, 0.35, 0.10),
    (1, 0): (0.90, 0.90, 0.90),
    (1, 1): (0.05, 0.10, 0.40),
}
