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

from . import compiled  # the threading layer, before any kernel runs

_CHUNK = 512  # pixels per parallel task


@numba.njit(cache=True, nogil=True, inline="always")
def _luminance(src: npt.NDArray[np.generic], q: int, d: np.float32,
               weights: npt.NDArray[np.float64]) -> float:
    """``Y`` of sample ``q`` of ``src (pixels, 3)``, each channel ``float32(x) / d`` (the float
    band's value), summed R, G, B in that order."""
    y: float = (weights[0] * (np.float32(src[q, 0]) / d) + weights[1] * (np.float32(src[q, 1]) / d)
                + weights[2] * (np.float32(src[q, 2]) / d))
    return y


@numba.njit(cache=True, parallel=True, nogil=True)
def _lrgb(band: npt.NDArray[np.generic], d: np.float32, pinv: npt.NDArray[np.float64],
          weights: npt.NDArray[np.float64], coeffs: npt.NDArray[np.float32],
          rgb: npt.NDArray[np.uint8]) -> None:
    # every loop runs over the chunk's pixels innermost (vectorised across pixels); each
    # pixel's sums still run over the lights in order, so the results are those of a pixel loop
    n, p = band.shape[0], band.shape[1]
    k = pinv.shape[0]
    for chunk in numba.prange((p + _CHUNK - 1) // _CHUNK):
        q0, q1 = chunk * _CHUNK, min(p, (chunk + 1) * _CHUNK)
        m = q1 - q0
        lum = np.empty((n, m))
        for i in range(n):
            src = band[i, q0:q1]
            for q in range(m):
                lum[i, q] = _luminance(src, q, d, weights)
        scale = lum[0].copy()  # the peak over the lights, then its inverse
        for i in range(1, n):
            for q in range(m):
                scale[q] = max(scale[q], lum[i, q])
        for q in range(m):
            scale[q] = 1.0 / scale[q] if scale[q] > 1e-6 else 0.0
        energy = np.zeros(m)
        proj = np.zeros((3, m))
        for i in range(n):
            src = band[i, q0:q1]
            for q in range(m):
                y = lum[i, q] * scale[q]
                lum[i, q] = y
                energy[q] += y * y
                proj[0, q] += (np.float32(src[q, 0]) / d) * y
                proj[1, q] += (np.float32(src[q, 1]) / d) * y
                proj[2, q] += (np.float32(src[q, 2]) / d) * y
        acc = np.empty(m)
        for t in range(k):
            acc[:] = 0.0
            for i in range(n):
                w = pinv[t, i]
                for q in range(m):
                    acc[q] += w * lum[i, q]
            for q in range(m):
                coeffs[q0 + q, t] = 255.0 * acc[q]
        for q in range(m):
            e = energy[q]
            inv = 1.0 / e if e > 1e-12 else 1.0
            for c in range(3):
                v = np.rint(proj[c, q] * inv * 255.0)
                rgb[q0 + q, c] = np.uint8(min(max(v, 0.0), 255.0))


def lrgb_band_compiled(band: npt.NDArray[np.generic], pinv: npt.NDArray[np.floating],
                       weights: tuple[float, float, float], div: float = 1.0
                       ) -> tuple[npt.NDArray[np.float32], npt.NDArray[np.uint8]]:
    """``coeffs (b, W, 6)`` float32 (0–255 units) and ``rgb (b, W, 3)`` uint8 of one band
    ``(N, b, W, 3)``: float32 in 0–1, or as decoded with ``div`` 255/65535 (each sample
    becomes ``float32(x) / div`` where it is read: the float band's values, so the same bits);
    ``pinv`` the ``(6, N)`` PTM pseudo-inverse."""
    n, b, w, _ = band.shape
    coeffs = np.empty((b * w, pinv.shape[0]), np.float32)
    rgb = np.empty((b * w, 3), np.uint8)
    _lrgb(compiled.kernel_samples(band).reshape(n, b * w, 3), np.float32(div),
          np.ascontiguousarray(pinv, np.float64), np.asarray(weights, np.float64), coeffs, rgb)
    return coeffs.reshape(b, w, -1), rgb.reshape(b, w, 3)


@numba.njit(cache=True, parallel=True, nogil=True)
def _lrgb_held_out(band: npt.NDArray[np.generic], d: np.float32,
                   pinv: npt.NDArray[np.float64],
                   weights: npt.NDArray[np.float64], train: npt.NDArray[np.intp],
                   held: npt.NDArray[np.intp], basis: npt.NDArray[np.float64],
                   sse: npt.NDArray[np.float64]) -> None:
    # as _lrgb: the chunk's pixels innermost, each pixel's sums over the lights in order, and
    # the chunk's squared errors summed over its pixels in order (the pixel loop's results)
    n_train, p, h = train.shape[0], band.shape[1], held.shape[0]
    k = pinv.shape[0]
    for chunk in numba.prange((p + _CHUNK - 1) // _CHUNK):
        q0, q1 = chunk * _CHUNK, min(p, (chunk + 1) * _CHUNK)
        m = q1 - q0
        y = np.empty((n_train, m))
        for j in range(n_train):
            src = band[train[j], q0:q1]
            for q in range(m):
                y[j, q] = _luminance(src, q, d, weights)
        scale = y[0].copy()
        for j in range(1, n_train):
            for q in range(m):
                scale[q] = max(scale[q], y[j, q])
        for q in range(m):
            scale[q] = 1.0 / scale[q] if scale[q] > 1e-6 else 0.0
        sums = np.zeros((4, m))  # energy, the colour's three projections
        for j in range(n_train):
            src = band[train[j], q0:q1]
            for q in range(m):
                yn = y[j, q] * scale[q]
                y[j, q] = yn
                sums[0, q] += yn * yn
                sums[1, q] += (np.float32(src[q, 0]) / d) * yn
                sums[2, q] += (np.float32(src[q, 1]) / d) * yn
                sums[3, q] += (np.float32(src[q, 2]) / d) * yn
        coeffs = np.zeros((k, m))
        for t in range(k):
            for j in range(n_train):
                w = pinv[t, j]
                for q in range(m):
                    coeffs[t, q] += w * y[j, q]
            for q in range(m):
                coeffs[t, q] *= 255.0
        rgb = np.empty((3, m))
        for q in range(m):
            e = sums[0, q]
            inv = 1.0 / e if e > 1e-12 else 1.0
            for c in range(3):
                rgb[c, q] = min(max(np.rint(sums[1 + c, q] * inv * 255.0), 0.0), 255.0) / 255.0
        lum = np.empty(m)
        err = np.empty(m)
        for mm in range(h):
            lum[:] = 0.0
            for t in range(k):
                b = basis[mm, t]
                for q in range(m):
                    lum[q] += coeffs[t, q] * b
            src = band[held[mm], q0:q1]
            for q in range(m):
                v = lum[q] / 255.0
                d0 = min(max(rgb[0, q] * v, 0.0), 1.0) - (np.float32(src[q, 0]) / d)
                d1 = min(max(rgb[1, q] * v, 0.0), 1.0) - (np.float32(src[q, 1]) / d)
                d2 = min(max(rgb[2, q] * v, 0.0), 1.0) - (np.float32(src[q, 2]) / d)
                err[q] = d0 * d0 + d1 * d1 + d2 * d2
            acc = 0.0
            for q in range(m):
                acc += err[q]
            sse[chunk, mm] += acc


def lrgb_held_out_compiled(band: npt.NDArray[np.generic], pinv: npt.NDArray[np.floating],
                           weights: tuple[float, float, float], train: npt.NDArray[np.intp],
                           held: npt.NDArray[np.intp], basis: npt.NDArray[np.floating],
                           div: float = 1.0) -> npt.NDArray[np.float64]:
    """Squared errors ``(h,)`` on the ``held`` lights of an LRGB PTM fitted to the ``train``
    lights of ``band (N, b, W, 3)`` (``pinv`` their ``(6, len(train))`` pseudo-inverse,
    ``basis (h, 6)`` the held-out lights' PTM weights): the fit of :func:`lrgb_band_compiled`
    and the prediction of :func:`~lanterna.tiler.fit.bands.predict_ptm_band` per pixel, without
    copying the training images.  Summed per chunk, then over chunks in order (deterministic)."""
    n, b, w, _ = band.shape
    flat = compiled.kernel_samples(band).reshape(n, b * w, 3)
    sse = np.zeros(((b * w + _CHUNK - 1) // _CHUNK, len(held)))
    _lrgb_held_out(flat, np.float32(div), np.ascontiguousarray(pinv, np.float64),
                   np.asarray(weights, np.float64),
                   np.ascontiguousarray(train, np.intp), np.ascontiguousarray(held, np.intp),
                   np.ascontiguousarray(basis, np.float64), sse)
    out: npt.NDArray[np.float64] = sse.sum(axis=0)
    return out

