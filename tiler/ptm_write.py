"""Write a :class:`~lanterna.tiler.ptm_model.Ptm` as an HP ``.ptm`` file.

The inverse of :func:`lanterna.tiler.ptm.read_ptm`: uncompressed formats are written byte for
byte, JPEG formats plane by plane with optional inter-plane prediction. Used by the tests to
build small files and by the demo generator.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import numpy as np
import numpy.typing as npt
import pyvips

from .errors import LanternaInputError
from .fileio import write_atomic
from .ptm_model import Ptm

PtmFormat = Literal[
    "PTM_FORMAT_RGB", "PTM_FORMAT_LRGB", "PTM_FORMAT_JPEG_RGB", "PTM_FORMAT_JPEG_LRGB"
]
_COLORSPACE = {
    "PTM_FORMAT_RGB": "rgb",
    "PTM_FORMAT_LRGB": "lrgb",
    "PTM_FORMAT_JPEG_RGB": "rgb",
    "PTM_FORMAT_JPEG_LRGB": "lrgb",
}


@dataclass(frozen=True)
class PtmPrediction:
    """Inter-plane prediction settings of a JPEG PTM, one entry per stream.

    Attributes
    ----------
    order:
        ``order[i] == k`` means stream ``i`` is decoded ``k``-th (a permutation of 0..n-1).
    reference:
        ``reference[i]`` is the plane stream ``i`` is predicted from, or -1 for none. The
        reference must be decoded earlier.
    transform:
        ``transform[i] & 1`` inverts the reference (``255 - ref``) before predicting.
    """

    order: Sequence[int]
    reference: Sequence[int]
    transform: Sequence[int]


def write_ptm(
    path: str | Path,
    ptm: Ptm,
    fmt: PtmFormat,
    *,
    version: str = "PTM_1.2",
    jpeg_quality: int = 90,
    prediction: PtmPrediction | None = None,
) -> None:
    """Write ``ptm`` to ``path`` atomically (a temporary file, then a rename).

    Parameters
    ----------
    path:
        Destination file.
    ptm:
        The PTM; its colorspace must match ``fmt``.
    fmt:
        The format line: ``PTM_FORMAT_RGB``, ``PTM_FORMAT_LRGB`` (byte-exact),
        ``PTM_FORMAT_JPEG_RGB`` (18 streams) or ``PTM_FORMAT_JPEG_LRGB`` (9 streams).
    version:
        ``"PTM_1.2"`` or ``"PTM_1.1"``; only changes the ``PTM_FORMAT_LRGB`` layout
        (1.1 interleaves the 6 coefficients and R, G, B per texel).
    jpeg_quality:
        JPEG quality 1–100 for the JPEG formats.
    prediction:
        JPEG only: decode order, reference planes and transforms. Predicted planes are
        encoded as residuals ``plane - ref' + 128`` against the *decoded* reference (so
        errors do not accumulate); residuals that had to be clipped to 0–255 are stored
        exactly as side-info records.

    Raises
    ------
    LanternaInputError
        If the arguments are inconsistent (format vs colorspace, bad version, bad
        prediction tables) or the file cannot be written.
    """
    dest = Path(path)
    colorspace = _COLORSPACE.get(fmt)
    if colorspace is None:
        raise LanternaInputError(dest, f"cannot write PTM format {fmt!r}")
    if colorspace != ptm.colorspace:
        raise LanternaInputError(dest, f"{fmt} needs an {colorspace} PTM, got {ptm.colorspace}")
    if version not in ("PTM_1.2", "PTM_1.1"):
        raise LanternaInputError(dest, f"cannot write PTM version {version!r}")
    header = _header(version, fmt, ptm)
    if fmt.startswith("PTM_FORMAT_JPEG_"):
        if not 1 <= jpeg_quality <= 100:
            raise LanternaInputError(dest, f"JPEG quality must be 1–100, got {jpeg_quality}")
        body = _jpeg_body(ptm, jpeg_quality, prediction, dest)
    else:
        if prediction is not None:
            raise LanternaInputError(dest, "prediction applies to JPEG formats only")
        body = [_raw_payload(ptm, version)]
    write_atomic(dest, [header, *body])


def _format_float(value: float) -> str:
    """Format like the real files (``2.000000``) unless that would lose float32 precision."""
    text = f"{value:.6f}"
    if np.float32(text) == np.float32(value):
        return text
    return repr(float(value))


def _header(version: str, fmt: str, ptm: Ptm) -> bytes:
    lines = [
        version,
        fmt,
        str(ptm.width),
        str(ptm.height),
        " ".join(_format_float(float(s)) for s in ptm.scale),
        " ".join(str(int(b)) for b in ptm.bias),
    ]
    return ("\n".join(lines) + "\n").encode("ascii")


def _raw_payload(ptm: Ptm, version: str) -> bytes:
    """Return the uncompressed payload, rows bottom-up."""
    if ptm.colorspace == "rgb":
        # (H, W, 3, 6) -> three colour blocks (3, H, W, 6), each bottom-up.
        return np.ascontiguousarray(ptm.coefficients.transpose(2, 0, 1, 3)[:, ::-1]).tobytes()
    assert ptm.rgb is not None
    if version == "PTM_1.1":
        texels = np.concatenate([ptm.coefficients, ptm.rgb], axis=2)
        return np.ascontiguousarray(texels[::-1]).tobytes()
    return (
        np.ascontiguousarray(ptm.coefficients[::-1]).tobytes()
        + np.ascontiguousarray(ptm.rgb[::-1]).tobytes()
    )


def ptm_planes(ptm: Ptm) -> npt.NDArray[np.uint8]:
    """Return the PTM's JPEG planes in stream order, ``(n, H, W)`` uint8, rows top-down.

    LRGB: planes 0–5 are a0..a5, 6–8 are R, G, B (n = 9). RGB: plane i is colour ``i // 6``,
    coefficient ``i % 6`` (n = 18).
    """
    if ptm.colorspace == "lrgb":
        assert ptm.rgb is not None
        planes = np.concatenate([ptm.coefficients, ptm.rgb], axis=2).transpose(2, 0, 1)
    else:
        planes = ptm.coefficients.transpose(2, 3, 0, 1).reshape(18, ptm.height, ptm.width)
    return np.ascontiguousarray(planes)


def _check_prediction(pred: PtmPrediction, n: int, dest: Path) -> None:
    if not len(pred.order) == len(pred.reference) == len(pred.transform) == n:
        raise LanternaInputError(dest, f"prediction tables must have {n} entries each")
    if sorted(pred.order) != list(range(n)):
        raise LanternaInputError(dest, f"prediction order must be a permutation of 0..{n - 1}")
    for i, r in enumerate(pred.reference):
        if r != -1 and (not 0 <= r < n or r == i or pred.order[r] >= pred.order[i]):
            raise LanternaInputError(dest, f"plane {i}: reference {r} is not decoded earlier")
    if any(t not in (0, 1) for t in pred.transform):
        raise LanternaInputError(dest, "prediction transforms must be 0 or 1")


def encode_jpeg_plane(plane: npt.NDArray[np.uint8], quality: int) -> bytes:
    """Encode an ``(H, W)`` uint8 plane (JPEG raster order) as a single-component JFIF."""
    if plane.ndim != 2 or plane.dtype != np.uint8:
        raise ValueError(f"expected an (H, W) uint8 plane, got {plane.shape} {plane.dtype}")
    h, w = plane.shape
    image = pyvips.Image.new_from_memory(np.ascontiguousarray(plane).tobytes(), w, h, 1, "uchar")
    data: bytes = image.jpegsave_buffer(Q=quality, keep="none")
    return data


def decode_jpeg_plane(data: bytes) -> npt.NDArray[np.uint8]:
    """Decode a single-component JPEG to an ``(H, W)`` uint8 array (JPEG raster order)."""
    image = pyvips.Image.jpegload_buffer(data)
    if image.bands != 1:
        raise ValueError(f"expected a single-band JPEG, got {image.bands} bands")
    pixels = image.write_to_memory()
    return np.frombuffer(pixels, dtype=np.uint8).reshape(image.height, image.width).copy()


def _jpeg_body(ptm: Ptm, quality: int, prediction: PtmPrediction | None, dest: Path) -> list[bytes]:
    # JPEG raster order is bottom-up, like the rest of the file.
    planes = ptm_planes(ptm)[:, ::-1]
    n = planes.shape[0]
    if prediction is None:
        prediction = PtmPrediction(tuple(range(n)), (-1,) * n, (0,) * n)
    _check_prediction(prediction, n, dest)
    streams: list[bytes] = [b""] * n
    sides: list[bytes] = [b""] * n
    decoded = np.zeros_like(planes)
    for i in sorted(range(n), key=lambda k: prediction.order[k]):
        target = planes[i].astype(np.int16)
        ref = prediction.reference[i]
        if ref < 0:
            streams[i] = encode_jpeg_plane(planes[i], quality)
            decoded[i] = decode_jpeg_plane(streams[i])
            continue
        base = decoded[ref].astype(np.int16)
        if prediction.transform[i] & 1:
            base = 255 - base
        wanted = target - base + 128
        residual = np.clip(wanted, 0, 255).astype(np.uint8)
        streams[i] = encode_jpeg_plane(residual, quality)
        values = (base + decode_jpeg_plane(streams[i]).astype(np.int16) - 128) % 256
        # Pixels whose residual was clipped, or whose JPEG error wrapped round 0/255, are
        # stored exactly as side info.
        index = np.flatnonzero((wanted != residual) | (np.abs(values - target) > 127))
        records = np.zeros((index.size, 5), dtype=np.uint8)
        records[:, :4] = (index[:, None] >> np.array([24, 16, 8, 0])) & 0xFF
        records[:, 4] = planes[i].reshape(-1)[index]
        sides[i] = records.tobytes()
        values.reshape(-1)[index] = planes[i].reshape(-1)[index]
        decoded[i] = values.astype(np.uint8)
    info = [
        str(quality),
        " ".join(str(t) for t in prediction.transform),
        " ".join("0" * n),
        " ".join("0" * n),
        " ".join(str(k) for k in prediction.order),
        " ".join(str(r) for r in prediction.reference),
        " ".join(str(len(s)) for s in streams),
        " ".join(str(len(s)) for s in sides),
    ]
    body = [("\n".join(info) + "\n").encode("ascii")]
    for stream, side in zip(streams, sides, strict=True):
        body += [stream, side]
    return body
