"""Luminance of a float band, compiled: ``Y = r·w₀ + g·w₁ + b·w₂`` per sample.

numpy's ``band @ weights`` runs a three-term dot per sample through its generic inner loop:
0.06 s of a 2048² 24-light normals fit and 0.19 s of a Ward fit (whose whole bands it reads).
Here one vectorised loop computes the same float32 products and sums in the same order (numba's
default maths: no fused multiply-add), so the same bits (tests/python/fit/test_fast_paths.py),
in half the time.  On one core: the loop is bound by memory, and split over both cores
it waited for the half that shared its core with the decoding thread (0.06 → 0.12 s).

:func:`luminance_rows` computes the same values for a chunk of pixels inside another kernel
(the photometric stereo's), so a fit that needs them only there never writes the band's
luminance out and reads it back.
"""

from __future__ import annotations

import numba
import numpy as np
import numpy.typing as npt

from .compiled import unit


@numba.njit(cache=True, nogil=True, inline="always")
def _weighted(src: npt.NDArray[np.generic], t: int, w0: np.float32, w1: np.float32,
              w2: np.float32, d: np.float32) -> np.float32:
    """The luminance of the sample ``src[t:t + 3]``: ``(r·w0 + g·w1) + b·w2``, each
    :func:`~.compiled.unit` of ``d`` (written once, so both kernels round alike)."""
    y: np.float32 = unit(src[t], d) * w0 + unit(src[t + 1], d) * w1 + unit(src[t + 2], d) * w2
    return y


@numba.njit(cache=True, nogil=True, error_model="numpy")
def luminance_rows(colour: npt.NDArray[np.generic], weights: npt.NDArray[np.float32],
                   q0: int, q1: int, d: np.float32, like: npt.NDArray[np.generic]
                   ) -> npt.NDArray[np.generic]:
    """``(N, q1 − q0)``: the luminances of pixels ``q0:q1`` of ``colour (N, P, 3)`` (each row
    C-contiguous), the values of :func:`luminance_compiled` (the same products, summed in the
    same order), stored in ``like``'s dtype (a compiled caller's other branch has it)."""
    n, m = colour.shape[0], q1 - q0
    y = np.empty((n, m), like.dtype)
    w0, w1, w2 = weights[0], weights[1], weights[2]
    for i in range(n):
        c = colour[i].reshape(-1)[3 * q0:3 * q1]
        yi = y[i]
        for q in range(m):
            yi[q] = _weighted(c, 3 * q, w0, w1, w2, d)
    return y


@numba.njit(cache=True, nogil=True)
def _luminance(src: npt.NDArray[np.generic], weights: npt.NDArray[np.float32],
               dst: npt.NDArray[np.float32], d: np.float32) -> None:
    """``dst[q]`` = luminance of ``src[3q:3q + 3]`` (each sample :func:`~.compiled.unit`),
    both contiguous."""
    w0, w1, w2 = weights[0], weights[1], weights[2]
    for q in range(dst.shape[0]):
        dst[q] = _weighted(src, 3 * q, w0, w1, w2, d)


def luminance_compiled(band: npt.NDArray[np.generic], weights: npt.NDArray[np.float32],
                       div: float = 1.0) -> npt.NDArray[np.float32]:
    """``(band / div) @ weights`` for a C-contiguous ``band (…, 3)``, float32 (``div`` 1) or
    8-/16-bit as decoded (``div`` 255/65535: each sample ``float32(x) / div`` first, the values
    of the float band), and float32 ``weights (3,)``: shape ``band.shape[:-1]``."""
    out = np.empty(band.shape[:-1], np.float32)
    _luminance(band.reshape(-1), weights, out.reshape(-1), np.float32(div))
    return out
