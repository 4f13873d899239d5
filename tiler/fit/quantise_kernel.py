"""The fitted layers' 8-bit bytes, compiled: the second pass of a PTM or HSH fit (float
coefficients → the layer's planes), and the bytes of the maps stored as they are (albedo, Ward's
kd, ks, gloss: :func:`unit_bytes`).

A spilled band holds the coefficients coefficient-major, ``(K, pixels, C)`` (``C`` = 3 colour
channels, or 1 for LRGB's luminance terms); each plane file stores three bytes per pixel, each
one coefficient of one channel (``plan[g, j] = (term, channel)``).  numpy quantised the whole
band, then gathered every plane's three bytes with a strided copy; here each byte is quantised
where it is written, in parallel over pixels, with the numpy formulas' float32 operations in
the same order — :func:`~lanterna.tiler.fit.ptm.ptm_quantize` (``rint(a / scale + bias)``) or
:func:`~lanterna.tiler.fit.hsh.hsh_quantize` (``rint((a − bias) / scale · 255)``), clipped to
0–255 — so the bytes are the same (tests/python/fit/test_fast_paths.py).  Where each plane holds
one term's three channels in order (HSH's planes) the plane is one contiguous run of the spill,
quantised by runs in a function of its own (:func:`_quantise_terms`): the loop over a strided
``(term, pixel, channel)`` gather does not vectorise, and the 2048² HSH layer's 113 M bytes took
0.13 s so, 0.024 s by runs.
"""

from __future__ import annotations

import numba
import numpy as np
import numpy.typing as npt

from . import compiled  # noqa: F401 - the threading layer, before any kernel runs

_CHUNK = 4096  # pixels per parallel task


@numba.njit(cache=True, nogil=True, inline="always")
def _byte(a: np.float32, s: np.float32, b: np.float32, hsh: bool) -> np.uint8:
    """The stored byte of coefficient ``a`` with its term's ``scale`` ``s`` and ``bias`` ``b``:
    HSH's formula if ``hsh``, else PTM's (float32 operations in numpy's order), clipped."""
    k255 = np.float32(255.0)
    v = np.rint((a - b) / s * k255) if hsh else np.rint(a / s + b)
    return np.uint8(min(max(v, np.float32(0.0)), k255))


@numba.njit(cache=True, parallel=True, nogil=True)
def _quantise(values: npt.NDArray[np.float32], scale: npt.NDArray[np.float32],
              bias: npt.NDArray[np.float32], plan: npt.NDArray[np.intp], hsh: bool,
              out: npt.NDArray[np.uint8]) -> None:
    p = values.shape[1]
    groups = plan.shape[0]
    for chunk in numba.prange((p + _CHUNK - 1) // _CHUNK):
        q0, q1 = chunk * _CHUNK, min(p, (chunk + 1) * _CHUNK)
        for g in range(groups):
            for j in range(3):
                t, c = plan[g, j, 0], plan[g, j, 1]
                s, b = scale[t], bias[t]
                for q in range(q0, q1):
                    out[g, q, j] = _byte(values[t, q, c], s, b, hsh)


@numba.njit(cache=True, nogil=True, inline="never")
def _quantise_run(src: npt.NDArray[np.float32], s: np.float32, b: np.float32, hsh: bool,
                  dst: npt.NDArray[np.uint8]) -> None:
    """``dst[i]`` = :func:`_byte` of ``src[i]``, both contiguous: a call of
    its own, so that the loop sees contiguous arrays and vectorises (inside a ``prange`` body,
    slices of reshaped arrays do not: the same loop there ran 5× slower)."""
    for i in range(src.shape[0]):
        dst[i] = _byte(src[i], s, b, hsh)


@numba.njit(cache=True, parallel=True, nogil=True)
def _quantise_terms(values: npt.NDArray[np.float32], scale: npt.NDArray[np.float32],
                    bias: npt.NDArray[np.float32], terms: npt.NDArray[np.intp], hsh: bool,
                    out: npt.NDArray[np.uint8]) -> None:
    """:func:`_quantise` for planes that each hold one term's three channels in order (HSH's):
    plane ``g`` is term ``terms[g]``'s run of ``values``, byte for byte."""
    groups, n = terms.shape[0], values.shape[1] * values.shape[2]
    run = 3 * _CHUNK
    chunks = (n + run - 1) // run
    for task in numba.prange(groups * chunks):
        g, chunk = task // chunks, task % chunks
        t = terms[g]
        a0, a1 = chunk * run, min(n, (chunk + 1) * run)
        _quantise_run(values[t].reshape(-1)[a0:a1], scale[t], bias[t], hsh,
                      out[g].reshape(-1)[a0:a1])


def quantise_planes(values: npt.NDArray[np.float32], scale: npt.NDArray[np.floating],
                    bias: npt.NDArray[np.floating], plan: npt.NDArray[np.intp], *, hsh: bool
                    ) -> npt.NDArray[np.uint8]:
    """``(G, pixels, 3)`` uint8: plane ``g``'s byte ``j`` of each pixel quantises coefficient
    ``plan[g, j, 0]`` of channel ``plan[g, j, 1]`` of ``values (K, pixels, C)`` float32, with
    that coefficient's ``scale`` and ``bias`` (HSH's formula if ``hsh``, else PTM's)."""
    plan = np.ascontiguousarray(plan, np.intp)
    out = np.empty((plan.shape[0], values.shape[1], 3), np.uint8)
    terms = plan[:, 0, 0]
    if values.shape[2] == 3 and (plan[:, :, 0] == terms[:, None]).all() and \
            (plan[:, :, 1] == np.arange(3)).all():  # each plane one term's R, G, B
        _quantise_terms(np.ascontiguousarray(values, np.float32), np.asarray(scale, np.float32),
                        np.asarray(bias, np.float32), np.ascontiguousarray(terms), hsh, out)
        return out
    _quantise(np.ascontiguousarray(values, np.float32), np.asarray(scale, np.float32),
              np.asarray(bias, np.float32), plan, hsh, out)
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
