"""The PCA bases' band step around its product, compiled: samples as decoded → light-major
floats, and float coefficients → the padded 8-bit planes.

:class:`~lanterna.tiler.fit.pca_band.PcaStep` projects a band's light samples onto the basis with
one BLAS product, ``kernel (N, n·3) @ x (n·3, P)``, on ``x`` light-major (row ``i·3 + k``: light
``i``, channel ``k``).  numpy made that layout in three passes (the 8-bit → float conversion,
the channel swap, a contiguous copy) and the planes in four more (``rint``, clip, cast, the
transpose and the zero padding of the last group).  Here each is one pass: :func:`light_major`
divides each sample once where it is written (the same correctly rounded ``x / 255`` as the float
band's, so the product sees the same floats), and :func:`quantise_planes` quantises each
coefficient with the same float32 operations where its byte goes, each group's bytes contiguous
(a plane image's rows, written without another copy) — so the bytes are those of the numpy
steps, bit for bit (tests/python/fit/test_pca_kernel.py).  Both run serially on the solving
thread: with ``prange`` their threads competed with the read-ahead decode for the two cores and
the pass took longer (2048², rbf 18: 1.02–1.12 s against 0.90 s).
"""

from __future__ import annotations

import numba
import numpy as np
import numpy.typing as npt

from . import compiled  # the threading layer, before any kernel runs


@numba.njit(cache=True, nogil=True)
def _light_major(band: npt.NDArray[np.generic], d: np.float32, p0: int,
                 out: npt.NDArray[np.float32]) -> None:
    n, p = band.shape[0], out.shape[1]
    for i in range(n):
        src = band[i, p0:p0 + p]
        r, g, b = out[3 * i], out[3 * i + 1], out[3 * i + 2]
        for q in range(p):
            r[q] = np.float32(src[q, 0]) / d
            g[q] = np.float32(src[q, 1]) / d
            b[q] = np.float32(src[q, 2]) / d


def light_major(band: npt.NDArray[np.generic], div: float = 1.0, pixels: slice | None = None,
                out: npt.NDArray[np.float32] | None = None) -> npt.NDArray[np.float32]:
    """``(n·3, P)`` float32 0–1 (row ``i·3 + k``: light ``i``, channel ``k``) of the pixels
    ``pixels`` (default all) of a band's samples ``(n, pixels, 3)``: 8/16-bit as decoded
    (``div`` 255/65535) or float (``div`` 1); into ``out`` when given (a reused buffer)."""
    n, total, _ = band.shape
    p0, p1, _ = (pixels or slice(None)).indices(total)
    res = np.empty((n * 3, p1 - p0), np.float32) if out is None else out
    _light_major(compiled.kernel_samples(band), np.float32(div), p0, res)
    return res


@numba.njit(cache=True, nogil=True)
def _quantise(coefficients: npt.NDArray[np.float32], lo: npt.NDArray[np.float32],
              gain: npt.NDArray[np.float32], out: npt.NDArray[np.uint8], p0: int) -> None:
    planes, p = coefficients.shape
    top, zero = np.float32(255.0), np.float32(0.0)
    for t in range(planes):
        src, a, s, dst = coefficients[t], lo[t], gain[t], out[t // 3]
        c = t % 3
        for q in range(p):
            v = np.rint((src[q] - a) * s)
            dst[p0 + q, c] = np.uint8(min(max(v, zero), top))
    for t in range(planes, 3 * out.shape[0]):  # the last group's unused channels
        dst, c = out[t // 3], t % 3
        for q in range(p):
            dst[p0 + q, c] = 0


def quantise_planes(coefficients: npt.NDArray[np.float32], lo: npt.NDArray[np.float32],
                    gain: npt.NDArray[np.float32], out: npt.NDArray[np.uint8],
                    p0: int = 0) -> None:
    """Plane ``t`` of coefficients ``(N, P)`` → channel ``t % 3`` of group ``t // 3`` of the
    pixels ``p0:p0 + P`` of ``out`` ``(groups, pixels, 3)`` (C-contiguous: each group one
    plane image's bytes): ``clip(rint((coefficients − lo) · gain), 0, 255)`` with float32
    ``lo`` and ``gain`` per plane; 0 past plane N."""
    _quantise(np.ascontiguousarray(coefficients, np.float32), np.ascontiguousarray(lo, np.float32),
              np.ascontiguousarray(gain, np.float32), out, p0)
