"""Luminance of a float band, compiled: ``Y = r·w₀ + g·w₁ + b·w₂`` per sample.

numpy's ``band @ weights`` runs a three-term dot per sample through its generic inner loop:
0.06 s of a 2048² 24-light normals fit and 0.19 s of a Ward fit (whose whole bands it reads).
Here one vectorised loop computes the same float32 products and sums in the same order (numba's
default maths: no fused multiply-add), so the same bits (tests/python/fit/test_fast_paths.py),
in half the time.  On one core: the loop is bound by memory, and split over both cores
it waited for the half that shared its core with the decoding thread (0.06 → 0.12 s).
"""

from __future__ import annotations

import numba
import numpy as np
import numpy.typing as npt

from . import compiled  # noqa: F401 - the threading layer, before any kernel runs


@numba.njit(cache=True, nogil=True)
def _luminance(src: npt.NDArray[np.float32], weights: npt.NDArray[np.float32],
               dst: npt.NDArray[np.float32]) -> None:
    """``dst[q]`` = luminance of ``src[3q:3q + 3]``, both contiguous."""
    w0, w1, w2 = weights[0], weights[1], weights[2]
    for q in range(dst.shape[0]):
        dst[q] = src[3 * q] * w0 + src[3 * q + 1] * w1 + src[3 * q + 2] * w2


def luminance_compiled(band: npt.NDArray[np.float32], weights: npt.NDArray[np.float32]
                       ) -> npt.NDArray[np.float32]:
    """``band @ weights`` for a C-contiguous float32 ``band (…, 3)`` and float32 ``weights (3,)``:
    shape ``band.shape[:-1]``."""
    out = np.empty(band.shape[:-1], np.float32)
    _luminance(band.reshape(-1), weights, out.reshape(-1))
    return out
