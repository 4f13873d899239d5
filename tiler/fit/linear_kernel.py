"""The linear models' band step, compiled: samples as stored → coefficients, range, held-out error.

A PTM (RGB) or HSH fit is a fixed product per sample: ``coeffs = rows @ x``, ``x`` the N lights'
values of one pixel's channel in 0–1, ``rows`` the ``(K, N)`` pseudo-inverse.  Its leave-one-out
report is another product, ``pred = held_rows @ x``, compared with the held-out samples.  numpy
made a float copy of the band first (the conversion), then one BLAS product per model and
another for the report, each a new array whose pages the kernel faults in.  Here one pass per
chunk of samples reads the bytes as decoded, divides each once into a small buffer (the same
correctly rounded ``x / 255`` as the float band's), and writes the coefficients straight into
their final place (the model's spill, :class:`~lanterna.tiler.fit.sinks.Spill`), with the
chunk's min/max and the held-out squared errors on the way.  The sums run in another order than
BLAS's, so coefficients agree with the numpy product to float32 rounding, not bit for bit
(tests/python/fit/test_linear_kernel.py).  A variant that kept BLAS for the product (a compiled
conversion into a reused buffer, one-thread ``sgemm`` into the spill, a compiled range and error
pass) was slower in the whole fit at 2048²: PTM 0.96 s against 0.72 s, HSH9 1.11 s against 0.90 s.
"""

from __future__ import annotations

import numba
import numpy as np
import numpy.typing as npt

from . import compiled  # noqa: F401 - the threading layer, before any kernel runs
from .spill_codes import code_row, mapped_codes, value_range

_CHUNK = 1024  # samples per parallel task: the chunk's N × 1024 float32 stay in L2


@numba.njit(cache=True, nogil=True, inline="always")
def _accumulate(rows: npt.NDArray[np.float32], t: int, x: npt.NDArray[np.float32],
                dst: npt.NDArray[np.float32]) -> None:
    """``dst = rows[t] @ x`` over the chunk: four lights per pass, so each output is stored
    once per four products (the loops over the samples vectorise)."""
    n, m = x.shape
    j = 0
    for q in range(m):
        dst[q] = np.float32(0.0)
    while j + 4 <= n:
        c0, c1, c2, c3 = rows[t, j], rows[t, j + 1], rows[t, j + 2], rows[t, j + 3]
        x0, x1, x2, x3 = x[j], x[j + 1], x[j + 2], x[j + 3]
        for q in range(m):
            dst[q] += (c0 * x0[q] + c1 * x1[q]) + (c2 * x2[q] + c3 * x3[q])
        j += 4
    while j < n:
        c0, x0 = rows[t, j], x[j]
        for q in range(m):
            dst[q] += c0 * x0[q]
        j += 1


@numba.njit(cache=True, nogil=True, inline="always")
def _held_error(held_rows: npt.NDArray[np.float32], i: int, x: npt.NDArray[np.float32],
                actual: npt.NDArray[np.float32], pred: npt.NDArray[np.float32]) -> float:
    """The squared error of held-out row ``i``'s predictions (clipped to 0–1) over the chunk."""
    _accumulate(held_rows, i, x, pred)
    one, zero = np.float32(1.0), np.float32(0.0)
    total = 0.0
    for q in range(pred.shape[0]):
        v = min(max(pred[q], zero), one) - actual[q]
        total += float(v) * float(v)
    return total


@numba.njit(cache=True, parallel=True, nogil=True)
def _linear(band: npt.NDArray[np.generic], div: float, rows: npt.NDArray[np.float32],
            held_rows: npt.NDArray[np.float32], held: npt.NDArray[np.intp],
            out: npt.NDArray[np.float32], at: int, lo: npt.NDArray[np.float32],
            hi: npt.NDArray[np.float32], sse: npt.NDArray[np.float64]) -> None:
    n, s = band.shape
    k, h = rows.shape[0], held_rows.shape[0]
    d = np.float32(div)
    for chunk in numba.prange((s + _CHUNK - 1) // _CHUNK):
        s0, s1 = chunk * _CHUNK, min(s, (chunk + 1) * _CHUNK)
        m = s1 - s0
        x = np.empty((n, m), np.float32)  # the chunk in 0-1, as the float band holds it
        for j in range(n):
            src, xj = band[j, s0:s1], x[j]
            for q in range(m):
                xj[q] = np.float32(src[q]) / d
        for t in range(k):
            dst = out[t, at + s0:at + s1]
            _accumulate(rows, t, x, dst)
            lo[chunk, t], hi[chunk, t] = value_range(dst)
        pred = np.empty(m, np.float32)
        for i in range(h):
            sse[chunk, i] = _held_error(held_rows, i, x, x[held[i]], pred)


def linear_band(band: npt.NDArray[np.generic], div: float, rows: npt.NDArray[np.float32],
                out: npt.NDArray[np.float32], at: int = 0,
                held_rows: npt.NDArray[np.float32] | None = None,
                held: npt.NDArray[np.intp] | None = None
                ) -> tuple[npt.NDArray[np.float32], npt.NDArray[np.float32],
                           npt.NDArray[np.float64]]:
    """Write ``rows @ (band / div)`` into ``out[:, at:at + S]``; return its per-row min and max
    and the held-out squared errors.

    ``band (N, S)`` holds the N lights' samples (8/16-bit as decoded with ``div`` 255/65535, or
    float in 0–1 with ``div`` 1); ``rows (K, N)``; ``out (K, ≥ at + S)`` float32, C-contiguous
    (a model's whole spill: compiled for a contiguous layout, its loops vectorise).
    ``held_rows (H, N)`` predict the samples ``band[held]``, each prediction clipped to 0–1;
    the squared errors are summed per held-out light, ``(H,)`` float64.  Each sample's sum
    runs over the lights in one fixed order, so the bits depend neither on the chunking nor on
    where the band starts.
    """
    n, s = band.shape
    k = rows.shape[0]
    hr = np.zeros((0, n), np.float32) if held_rows is None else held_rows
    hi_ = np.zeros(0, np.intp) if held is None else np.ascontiguousarray(held, np.intp)
    chunks = max(1, (s + _CHUNK - 1) // _CHUNK)
    lo = np.full((chunks, k), np.inf, np.float32)
    hi = np.full((chunks, k), -np.inf, np.float32)
    sse = np.zeros((chunks, hr.shape[0]), np.float64)
    if s:
        _linear(band, float(div), np.ascontiguousarray(rows, np.float32),
                np.ascontiguousarray(hr, np.float32), hi_, out, at, lo, hi, sse)
    return lo.min(axis=0), hi.max(axis=0), sse.sum(axis=0)


@numba.njit(cache=True, parallel=True, nogil=True)
def _linear_coded(band: npt.NDArray[np.generic], div: float, rows: npt.NDArray[np.float32],
                  held_rows: npt.NDArray[np.float32], held: npt.NDArray[np.intp],
                  codes: npt.NDArray[np.uint16], row_lo: npt.NDArray[np.float32],
                  row_hi: npt.NDArray[np.float32], sse: npt.NDArray[np.float64]) -> None:
    n, s = band.shape
    k, h = rows.shape[0], held_rows.shape[0]
    b, r = codes.shape[1], codes.shape[2]
    d = np.float32(div)
    for y in numba.prange(b):
        vals = np.empty((k, r), np.float32)  # the row's coefficients, then coded
        x = np.empty((n, _CHUNK), np.float32)
        pred = np.empty(_CHUNK, np.float32)
        for c0 in range(0, r, _CHUNK):
            m = min(r, c0 + _CHUNK) - c0
            s0 = y * r + c0
            for j in range(n):
                src, xj = band[j, s0:s0 + m], x[j]
                for q in range(m):
                    xj[q] = np.float32(src[q]) / d
            xv = x[:, :m]
            for t in range(k):
                _accumulate(rows, t, xv, vals[t, c0:c0 + m])
            for i in range(h):
                sse[y, i] += _held_error(held_rows, i, xv, xv[held[i]], pred[:m])
        for t in range(k):
            a, z = value_range(vals[t])
            row_lo[t, y], row_hi[t, y] = a, z
            code_row(vals[t], a, z, codes[t, y])


def linear_band_coded(band: npt.NDArray[np.generic], div: float, rows: npt.NDArray[np.float32],
                      width: int, held_rows: npt.NDArray[np.float32] | None = None,
                      held: npt.NDArray[np.intp] | None = None
                      ) -> tuple[npt.NDArray[np.uint16], npt.NDArray[np.float32],
                                 npt.NDArray[np.float32], npt.NDArray[np.float64]]:
    """:func:`linear_band` of a band of whole image rows (``S = b · width``), its coefficients
    coded per row as it goes (:func:`~.spill_codes.encode_rows`, the same codes): ``codes
    (K, b, width)``, the rows' ``lo``, ``hi`` ``(K, b)`` and the held-out squared errors."""
    n, s = band.shape
    k = rows.shape[0]
    b = s // width if width else 0
    hr = np.zeros((0, n), np.float32) if held_rows is None else held_rows
    hi_ = np.zeros(0, np.intp) if held is None else np.ascontiguousarray(held, np.intp)
    codes = mapped_codes((k, b, width))
    row_lo = np.zeros((k, b), np.float32)
    row_hi = np.zeros((k, b), np.float32)
    sse = np.zeros((b, hr.shape[0]), np.float64)
    if s:
        _linear_coded(band, float(div), np.ascontiguousarray(rows, np.float32),
                      np.ascontiguousarray(hr, np.float32), hi_, codes, row_lo, row_hi, sse)
    return codes, row_lo, row_hi, sse.sum(axis=0)
