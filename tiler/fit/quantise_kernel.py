"""The fitted layers' 8-bit bytes, compiled: the second pass of a PTM or HSH fit (a spilled
band's coefficient codes → the layer's planes), and the bytes of the maps stored as they are
(albedo, Ward's kd, ks, gloss: :func:`unit_bytes`).

A spilled band holds 16-bit codes coefficient-major, ``(K, rows, W · C)`` (``C`` = 3 colour
channels, or 1 for LRGB's luminance terms), with each term's row range
(:mod:`~lanterna.tiler.fit.spill_codes`); each plane file stores three bytes per pixel, each
one coefficient of one channel (``plan[g, j] = (term, channel)``).  Each byte is made where it
is written, in parallel over rows: the code's value (:func:`~.spill_codes.code_value`), then the
numpy formulas' float32 operations in the same order —
:func:`~lanterna.tiler.fit.ptm.ptm_quantize` (``rint(a / scale + bias)``) or
:func:`~lanterna.tiler.fit.hsh.hsh_quantize` (``rint((a − bias) / scale · 255)``), clipped to
0–255 — so the bytes are those of the numpy formula on the decoded values
(tests/python/fit/test_fast_paths.py).  Where each plane holds one term's three channels in
order (HSH's planes) a plane's row is one contiguous run of the band's codes, quantised in a
function of its own (:func:`_quantise_run`): the loop over a strided ``(term, pixel, channel)``
gather does not vectorise, and the 2048² HSH layer's 113 M bytes took 0.13 s so, 0.024 s by
runs (from float32; from codes, 0.07 s).
"""

from __future__ import annotations

import numba
import numpy as np
import numpy.typing as npt

from . import compiled  # noqa: F401 - the threading layer, before any kernel runs
from .spill_codes import code_value, row_step


@numba.njit(cache=True, nogil=True, inline="always")
def _byte(a: np.float32, s: np.float32, b: np.float32, hsh: bool) -> np.uint8:
    """The stored byte of coefficient ``a`` with its term's ``scale`` ``s`` and ``bias`` ``b``:
    HSH's formula if ``hsh``, else PTM's (float32 operations in numpy's order), clipped."""
    k255 = np.float32(255.0)
    v = np.rint((a - b) / s * k255) if hsh else np.rint(a / s + b)
    return np.uint8(min(max(v, np.float32(0.0)), k255))


@numba.njit(cache=True, parallel=True, nogil=True)
def _quantise(codes: npt.NDArray[np.uint16], row_lo: npt.NDArray[np.float32],
              row_hi: npt.NDArray[np.float32], scale: npt.NDArray[np.float32],
              bias: npt.NDArray[np.float32], plan: npt.NDArray[np.intp], hsh: bool,
              out: npt.NDArray[np.uint8]) -> None:
    b = codes.shape[1]
    c = codes.shape[2] // (out.shape[1] // b)  # samples per pixel
    w = out.shape[1] // b
    groups = plan.shape[0]
    for task in numba.prange(b * groups):
        y, g = task // groups, task % groups
        for j in range(3):
            t, ch = plan[g, j, 0], plan[g, j, 1]
            s, bi = scale[t], bias[t]
            base, step = row_step(row_lo[t, y], row_hi[t, y])
            src = codes[t, y]
            for x in range(w):
                out[g, y * w + x, j] = _byte(code_value(src[x * c + ch], base, step), s, bi,
                                             hsh)


@numba.njit(cache=True, nogil=True, inline="never")
def _quantise_run(src: npt.NDArray[np.uint16], base: float, step: float, s: np.float32,
                  b: np.float32, hsh: bool, dst: npt.NDArray[np.uint8]) -> None:
    """``dst[i]`` = :func:`_byte` of code ``src[i]``'s value, both contiguous: a call of
    its own, so that the loop sees contiguous arrays and vectorises (inside a ``prange`` body,
    slices of reshaped arrays do not: the same loop there ran 5× slower)."""
    for i in range(src.shape[0]):
        dst[i] = _byte(code_value(src[i], base, step), s, b, hsh)


@numba.njit(cache=True, parallel=True, nogil=True)
def _quantise_terms(codes: npt.NDArray[np.uint16], row_lo: npt.NDArray[np.float32],
                    row_hi: npt.NDArray[np.float32], scale: npt.NDArray[np.float32],
                    bias: npt.NDArray[np.float32], terms: npt.NDArray[np.intp], hsh: bool,
                    out: npt.NDArray[np.uint8]) -> None:
    """:func:`_quantise` for planes that each hold one term's three channels in order (HSH's):
    plane ``g``'s bytes of row ``y`` are term ``terms[g]``'s codes of that row, in order."""
    groups, b, r = terms.shape[0], codes.shape[1], codes.shape[2]
    for task in numba.prange(groups * b):
        g, y = task // b, task % b
        t = terms[g]
        base, step = row_step(row_lo[t, y], row_hi[t, y])
        _quantise_run(codes[t, y], base, step, scale[t], bias[t], hsh,
                      out[g].reshape(-1)[y * r:(y + 1) * r])


def quantise_planes(codes: npt.NDArray[np.uint16], row_lo: npt.NDArray[np.float32],
                    row_hi: npt.NDArray[np.float32], scale: npt.NDArray[np.floating],
                    bias: npt.NDArray[np.floating], plan: npt.NDArray[np.intp], *, hsh: bool,
                    channels: int) -> npt.NDArray[np.uint8]:
    """``(G, pixels, 3)`` uint8: plane ``g``'s byte ``j`` of each pixel quantises coefficient
    ``plan[g, j, 0]`` of channel ``plan[g, j, 1]``, with that coefficient's ``scale`` and
    ``bias`` (HSH's formula if ``hsh``, else PTM's), of the values of a spilled band's codes
    ``(K, rows, W · channels)`` and its rows' ranges ``(K, rows)``
    (:func:`~.spill_codes.encode_rows`; each value :func:`~.spill_codes.code_value`)."""
    plan = np.ascontiguousarray(plan, np.intp)
    k, b, r = codes.shape
    out = np.empty((plan.shape[0], b * (r // channels), 3), np.uint8)
    if not out.size:
        return out
    terms = plan[:, 0, 0]
    args = (np.ascontiguousarray(codes, np.uint16), np.ascontiguousarray(row_lo, np.float32),
            np.ascontiguousarray(row_hi, np.float32), np.asarray(scale, np.float32),
            np.asarray(bias, np.float32))
    if channels == 3 and (plan[:, :, 0] == terms[:, None]).all() and \
            (plan[:, :, 1] == np.arange(3)).all():  # each plane one term's R, G, B
        _quantise_terms(*args, np.ascontiguousarray(terms), hsh, out)
        return out
    _quantise(*args, plan, hsh, out)
    return out


@numba.njit(cache=True, nogil=True)
def _unit_bytes(values: npt.NDArray[np.floating], lo: float, span: float,
                out: npt.NDArray[np.uint8]) -> None:
    src, dst = values.reshape(-1), out.reshape(-1)
    for i in range(src.size):
        v = np.rint((np.float64(src[i]) - lo) / span * 255.0)
        dst[i] = np.uint8(min(max(v, 0.0), 255.0))


def unit_bytes(values: npt.NDArray[np.generic], lo: float = 0.0, hi: float = 1.0
               ) -> npt.NDArray[np.uint8]:
    """The 8-bit levels of ``values`` over ``lo``–``hi``: ``clip(rint((v − lo)/(hi − lo)·255),
    0, 255)`` in float64, numpy's formula byte for byte (tests/python/fit/test_fast_paths.py), in
    one loop on the calling thread (numpy's four passes and three float64 temporaries took
    0.19 s of a 2048² Ward fit's main thread; NaN gives 0)."""
    src = np.ascontiguousarray(values)
    if src.dtype not in (np.float32, np.float64):
        src = src.astype(np.float64)
    out = np.empty(src.shape, np.uint8)
    _unit_bytes(src, float(lo), float(hi) - float(lo), out)
    return out
