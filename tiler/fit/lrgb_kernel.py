"""The LRGB PTM band fit of :func:`~lanterna.tiler.fit.bands.ptm_lrgb_band`, compiled per pixel.

numpy makes six passes over the band for it (luminance, peak, normalisation, the coefficient
product, the colour's energy and projection, each a full-size temporary); compiled, a pixel reads
its N samples once: ``Y = 0.2125 R + 0.7154 G + 0.0721 B``, ``Yn = Y / max Y`` (0 where the peak
is ≤ 1e-6), the six coefficients ``255 · pinv @ Yn`` and the colour ``rint(255 · Σ c·Yn / Σ Yn²)``
(÷ 1 where ``Σ Yn² ≤ 1e-12``).  Sums run in float64, so the coefficients agree with the numpy
reference (``compiled=False``) to float32 rounding and a colour byte may differ by one where
``255 · colour`` is within rounding of a half (tests/python/fit/test_engine_kernels.py).
"""

from __future__ import annotations

import numba
import numpy as np
import numpy.typing as npt

from . import compiled  # noqa: F401 - the threading layer, before any kernel runs

_CHUNK = 512  # pixels per parallel task


@numba.njit(cache=True, parallel=True, nogil=True)
def _lrgb(band: npt.NDArray[np.float32], pinv: npt.NDArray[np.float64],
          weights: npt.NDArray[np.float64], coeffs: npt.NDArray[np.float32],
          rgb: npt.NDArray[np.uint8]) -> None:
    n, p = band.shape[0], band.shape[1]
    k = pinv.shape[0]
    for chunk in numba.prange((p + _CHUNK - 1) // _CHUNK):
        q0, q1 = chunk * _CHUNK, min(p, (chunk + 1) * _CHUNK)
        lum = np.empty((q1 - q0, n))
        for i in range(n):  # light-major input read in order, into pixel-major luminance
            for q in range(q0, q1):
                lum[q - q0, i] = (weights[0] * band[i, q, 0] + weights[1] * band[i, q, 1]
                                  + weights[2] * band[i, q, 2])
        proj = np.zeros((q1 - q0, 3))
        energy = np.zeros(q1 - q0)
        for q in range(q0, q1):
            y = lum[q - q0]
            peak = y.max()
            scale = 1.0 / peak if peak > 1e-6 else 0.0
            for i in range(n):
                y[i] *= scale
                energy[q - q0] += y[i] * y[i]
            for t in range(k):
                acc = 0.0
                for i in range(n):
                    acc += pinv[t, i] * y[i]
                coeffs[q, t] = 255.0 * acc
        for i in range(n):
            for q in range(q0, q1):
                yn = lum[q - q0, i]
                for c in range(3):
                    proj[q - q0, c] += band[i, q, c] * yn
        for q in range(q0, q1):
            e = energy[q - q0]
            inv = 1.0 / e if e > 1e-12 else 1.0
            for c in range(3):
                v = np.rint(proj[q - q0, c] * inv * 255.0)
                rgb[q, c] = np.uint8(min(max(v, 0.0), 255.0))


def lrgb_band_compiled(band: npt.NDArray[np.float32], pinv: npt.NDArray[np.floating],
                       weights: tuple[float, float, float]
                       ) -> tuple[npt.NDArray[np.float32], npt.NDArray[np.uint8]]:
    """``coeffs (b, W, 6)`` float32 (0–255 units) and ``rgb (b, W, 3)`` uint8 of one band
    ``(N, b, W, 3)`` float32 in 0–1, ``pinv`` the ``(6, N)`` PTM pseudo-inverse."""
    n, b, w, _ = band.shape
    coeffs = np.empty((b * w, pinv.shape[0]), np.float32)
    rgb = np.empty((b * w, 3), np.uint8)
    _lrgb(np.ascontiguousarray(band, np.float32).reshape(n, b * w, 3),
          np.ascontiguousarray(pinv, np.float64), np.asarray(weights, np.float64), coeffs, rgb)
    return coeffs.reshape(b, w, -1), rgb.reshape(b, w, 3)
