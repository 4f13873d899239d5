"""The LRGB PTM band fit of :func:`~lanterna.tiler.fit.bands.ptm_lrgb_band` and its
leave-one-out twin, compiled (Numba), in one pass over the band.

numpy makes six passes over the band for it (luminance, peak, normalisation, the coefficient
product, the colour's energy and projection, each a full-size temporary); compiled, each chunk
of pixels is read once: its samples made 0–1 floats once (``float32(x) / div``, by a table of
the 256 or 65536 values for 8- and 16-bit samples: the same bits as the division), one plane
per channel, then ``Y = 0.2125 R + 0.7154 G + 0.0721 B``, ``Yn = Y / max Y`` (0 where the peak
is ≤ 1e-6), the six coefficients ``255 · pinv @ Yn`` and the colour
``rint(255 · Σ c·Yn / Σ Yn²)`` (÷ 1 where ``Σ Yn² ≤ 1e-12``).  The leave-one-out report runs the
same steps on the training lights' luminances (the same values) and predicts the held-out
lights as :func:`~lanterna.tiler.fit.bands.predict_ptm_band` does.  Sums run in float64, so the
coefficients agree with the numpy reference (``compiled=False``) to float32 rounding and a
colour byte may differ by one where ``255 · colour`` is within rounding of a half
(tests/python/fit/test_engine_kernels.py).  Every loop runs over the chunk's pixels innermost
(vectorised across pixels); each pixel's sums still run over the lights in order.
"""

from __future__ import annotations

from functools import lru_cache

import numba
import numpy as np
import numpy.typing as npt

from . import compiled

_CHUNK = 512  # pixels per parallel task
F64 = npt.NDArray[np.float64]


@numba.njit(cache=True, nogil=True)
def _planes(band: npt.NDArray[np.generic], q0: int, q1: int, d: np.float32,
            table: npt.NDArray[np.float32]) -> npt.NDArray[np.float32]:
    """``(3, N, m)``: pixels ``q0:q1`` of ``band (N, P, 3)`` as ``float32(x) / d``, from
    ``table`` (the values of every 8-/16-bit sample) when it is not empty."""
    n, m = band.shape[0], q1 - q0
    out = np.empty((3, n, m), np.float32)
    for i in range(n):
        src = band[i, q0:q1]
        for c in range(3):
            row = out[c, i]
            if table.shape[0] > 0:
                for q in range(m):
                    row[q] = table[np.intp(src[q, c])]
            else:
                for q in range(m):
                    row[q] = np.float32(src[q, c]) / d
    return out


@numba.njit(cache=True, nogil=True)
def _luminance(planes: npt.NDArray[np.float32], weights: F64) -> F64:
    """``(N, m)``: ``Y`` of every sample, summed R, G, B in that order."""
    n, m = planes.shape[1], planes.shape[2]
    lum = np.empty((n, m))
    for i in range(n):
        r, g, b = planes[0, i], planes[1, i], planes[2, i]
        for q in range(m):
            lum[i, q] = weights[0] * r[q] + weights[1] * g[q] + weights[2] * b[q]
    return lum


@numba.njit(cache=True, nogil=True)
def _fit(planes: npt.NDArray[np.float32], y: F64, rows: npt.NDArray[np.intp], pinv: F64
         ) -> tuple[F64, F64]:
    """The LRGB fit of the lights ``rows`` from ``y (len(rows), m)``, their luminances
    (normalised in place): coefficients ``(6, m)`` in 0–255 units and colour ``(3, m)``, its
    0–255 byte values."""
    n, m, k = rows.shape[0], y.shape[1], pinv.shape[0]
    scale = y[0].copy()  # the peak over the lights, then its inverse
    for j in range(1, n):
        for q in range(m):
            scale[q] = max(scale[q], y[j, q])
    for q in range(m):
        scale[q] = 1.0 / scale[q] if scale[q] > 1e-6 else 0.0
    energy = np.zeros(m)
    proj = np.zeros((3, m))
    for j in range(n):
        r, g, b = planes[0, rows[j]], planes[1, rows[j]], planes[2, rows[j]]
        for q in range(m):
            yn = y[j, q] * scale[q]
            y[j, q] = yn
            energy[q] += yn * yn
            proj[0, q] += r[q] * yn
            proj[1, q] += g[q] * yn
            proj[2, q] += b[q] * yn
    coeffs = np.zeros((k, m))
    for t in range(k):
        for j in range(n):
            w = pinv[t, j]
            for q in range(m):
                coeffs[t, q] += w * y[j, q]
        for q in range(m):
            coeffs[t, q] *= 255.0
    for q in range(m):
        e = energy[q]
        inv = 1.0 / e if e > 1e-12 else 1.0
        for c in range(3):
            proj[c, q] = min(max(np.rint(proj[c, q] * inv * 255.0), 0.0), 255.0)
    return coeffs, proj


@numba.njit(cache=True, parallel=True, nogil=True)
def _lrgb(band: npt.NDArray[np.generic], d: np.float32, table: npt.NDArray[np.float32],
          weights: F64, pinv: F64, coeffs: npt.NDArray[np.float32], rgb: npt.NDArray[np.uint8],
          pinv_t: F64, train: npt.NDArray[np.intp], held: npt.NDArray[np.intp], basis: F64,
          sse: F64) -> None:
    # the layer when ``coeffs`` has rows, the report when ``held`` is not empty
    n, p, h = band.shape[0], band.shape[1], held.shape[0]
    rows = np.arange(n)
    for chunk in numba.prange((p + _CHUNK - 1) // _CHUNK):
        q0, q1 = chunk * _CHUNK, min(p, (chunk + 1) * _CHUNK)
        m = q1 - q0
        planes = _planes(band, q0, q1, d, table)
        lum = _luminance(planes, weights)
        if h > 0:
            y = np.empty((train.shape[0], m))
            for j in range(train.shape[0]):
                y[j] = lum[train[j]]
            tc, tp = _fit(planes, y, train, pinv_t)
            _held_out(planes, tc, tp, held, basis, sse[chunk])
        if coeffs.shape[0] > 0:
            c6, colour = _fit(planes, lum, rows, pinv)
            for q in range(m):
                for t in range(c6.shape[0]):
                    coeffs[q0 + q, t] = c6[t, q]
                for c in range(3):
                    rgb[q0 + q, c] = np.uint8(colour[c, q])


@numba.njit(cache=True, nogil=True)
def _held_out(planes: npt.NDArray[np.float32], coeffs: F64, colour: F64,
              held: npt.NDArray[np.intp], basis: F64, sse: F64) -> None:
    """Add to ``sse (h,)`` the chunk's squared errors on the ``held`` lights of the fit
    ``coeffs``/``colour`` (:func:`_fit`'s): ``clip(rgb · L/255, 0, 1)`` against the samples,
    summed over the pixels in order."""
    k, m = coeffs.shape
    rgb = np.empty((3, m))
    for q in range(m):
        for c in range(3):
            rgb[c, q] = colour[c, q] / 255.0
    lum = np.empty(m)
    err = np.empty(m)
    for mm in range(held.shape[0]):
        lum[:] = 0.0
        for t in range(k):
            b = basis[mm, t]
            for q in range(m):
                lum[q] += coeffs[t, q] * b
        r, g, bl = planes[0, held[mm]], planes[1, held[mm]], planes[2, held[mm]]
        for q in range(m):
            v = lum[q] / 255.0
            d0 = min(max(rgb[0, q] * v, 0.0), 1.0) - r[q]
            d1 = min(max(rgb[1, q] * v, 0.0), 1.0) - g[q]
            d2 = min(max(rgb[2, q] * v, 0.0), 1.0) - bl[q]
            err[q] = d0 * d0 + d1 * d1 + d2 * d2
        acc = 0.0
        for q in range(m):
            acc += err[q]
        sse[mm] += acc


@lru_cache(maxsize=4)
def _table(dtype: str, div: float) -> npt.NDArray[np.float32]:
    """``float32(x) / div`` of every value of an 8-/16-bit ``dtype`` (empty for others)."""
    if dtype not in ("uint8", "uint16"):
        return np.zeros(0, np.float32)
    values = np.arange(256 if dtype == "uint8" else 65536, dtype=np.float32)
    out: npt.NDArray[np.float32] = values / np.float32(div)
    return out


def lrgb_band_held_out_compiled(
        band: npt.NDArray[np.generic], pinv: npt.NDArray[np.floating] | None,
        weights: tuple[float, float, float], div: float = 1.0,
        held_out: tuple[npt.NDArray[np.floating], npt.NDArray[np.intp], npt.NDArray[np.intp],
                        npt.NDArray[np.floating]] | None = None
) -> tuple[npt.NDArray[np.float32], npt.NDArray[np.uint8], npt.NDArray[np.float64]]:
    """The layer and the report of one band ``(N, b, W, 3)`` in one pass: float32 in 0–1, or
    as decoded with ``div`` 255/65535 (each sample becomes ``float32(x) / div``: the float
    band's values, so the same bits).

    ``pinv`` the ``(6, N)`` PTM pseudo-inverse gives ``coeffs (b, W, 6)`` float32 (0–255
    units) and ``rgb (b, W, 3)`` uint8 (``None``: no layer, both empty).
    ``held_out = (pinv_t, train, held, basis)`` — the training lights' ``(6, len(train))``
    pseudo-inverse, the two index lists, the held-out lights' PTM weights ``(h, 6)`` — gives
    the squared errors ``(h,)`` on the held lights of the fit of the training ones, without
    copying them: summed per chunk, then over the chunks in order (deterministic)."""
    n, b, w, _ = band.shape
    flat = compiled.kernel_samples(band).reshape(n, b * w, 3)
    rows = 0 if pinv is None else b * w
    coeffs = np.empty((rows, 6), np.float32)
    rgb = np.empty((rows, 3), np.uint8)
    none = (np.zeros((6, 0)), np.zeros(0, np.intp), np.zeros(0, np.intp), np.zeros((0, 6)))
    pinv_t, train, held, basis = none if held_out is None else held_out
    sse = np.zeros(((b * w + _CHUNK - 1) // _CHUNK, len(held)))
    _lrgb(flat, np.float32(div), _table(str(flat.dtype), float(div)),
          np.asarray(weights, np.float64),
          np.zeros((6, n)) if pinv is None else np.ascontiguousarray(pinv, np.float64),
          coeffs, rgb, np.ascontiguousarray(pinv_t, np.float64),
          np.ascontiguousarray(train, np.intp), np.ascontiguousarray(held, np.intp),
          np.ascontiguousarray(basis, np.float64), sse)
    total: npt.NDArray[np.float64] = sse.sum(axis=0)
    if pinv is None:
        return coeffs, rgb, total
    return coeffs.reshape(b, w, 6), rgb.reshape(b, w, 3), total


def lrgb_band_compiled(band: npt.NDArray[np.generic], pinv: npt.NDArray[np.floating],
                       weights: tuple[float, float, float], div: float = 1.0
                       ) -> tuple[npt.NDArray[np.float32], npt.NDArray[np.uint8]]:
    """The layer alone (:func:`lrgb_band_held_out_compiled`)."""
    coeffs, rgb, _ = lrgb_band_held_out_compiled(band, pinv, weights, div)
    return coeffs, rgb
