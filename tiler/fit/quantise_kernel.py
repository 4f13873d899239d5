"""The second pass of a PTM or HSH fit, compiled: float coefficients → the layer's 8-bit planes.

A spilled band holds the coefficients coefficient-major, ``(K, pixels, C)`` (``C`` = 3 colour
channels, or 1 for LRGB's luminance terms); each plane file stores three bytes per pixel, each
one coefficient of one channel (``plan[g, j] = (term, channel)``).  numpy quantised the whole
band, then gathered every plane's three bytes with a strided copy; here each byte is quantised
where it is written, in parallel over pixels, with the numpy formulas' float32 operations in
the same order — :func:`~lanterna.tiler.fit.ptm.ptm_quantize` (``rint(a / scale + bias)``) or
:func:`~lanterna.tiler.fit.hsh.hsh_quantize` (``rint((a − bias) / scale · 255)``), clipped to
0–255 — so the bytes are the same (tests/python/fit/test_fast_paths.py).
"""

from __future__ import annotations

import numba
import numpy as np
import numpy.typing as npt

from . import compiled  # noqa: F401 - the threading layer, before any kernel runs

_CHUNK = 4096  # pixels per parallel task


@numba.njit(cache=True, parallel=True, nogil=True)
def _quantise(values: npt.NDArray[np.float32], scale: npt.NDArray[np.float32],
              bias: npt.NDArray[np.float32], plan: npt.NDArray[np.intp], hsh: bool,
              out: npt.NDArray[np.uint8]) -> None:
    p = values.shape[1]
    groups = plan.shape[0]
    k255 = np.float32(255.0)
    for chunk in numba.prange((p + _CHUNK - 1) // _CHUNK):
        q0, q1 = chunk * _CHUNK, min(p, (chunk + 1) * _CHUNK)
        for g in range(groups):
            for j in range(3):
                t, c = plan[g, j, 0], plan[g, j, 1]
                s, b = scale[t], bias[t]
                for q in range(q0, q1):
                    a = values[t, q, c]
                    v = np.rint((a - b) / s * k255) if hsh else np.rint(a / s + b)
                    out[g, q, j] = np.uint8(min(max(v, np.float32(0.0)), k255))


def quantise_planes(values: npt.NDArray[np.float32], scale: npt.NDArray[np.floating],
                    bias: npt.NDArray[np.floating], plan: npt.NDArray[np.intp], *, hsh: bool
                    ) -> npt.NDArray[np.uint8]:
    """``(G, pixels, 3)`` uint8: plane ``g``'s byte ``j`` of each pixel quantises coefficient
    ``plan[g, j, 0]`` of channel ``plan[g, j, 1]`` of ``values (K, pixels, C)`` float32, with
    that coefficient's ``scale`` and ``bias`` (HSH's formula if ``hsh``, else PTM's)."""
    plan = np.ascontiguousarray(plan, np.intp)
    out = np.empty((plan.shape[0], values.shape[1], 3), np.uint8)
    _quantise(np.ascontiguousarray(values, np.float32), np.asarray(scale, np.float32),
              np.asarray(bias, np.float32), plan, hsh, out)
    return out
