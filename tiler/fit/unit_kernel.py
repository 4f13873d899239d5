"""The 8-/16-bit → float32 (0–1) conversion of the fit's sub-bands, compiled.

:func:`~lanterna.tiler.inputs.stack.to_unit` divides with numpy, which casts the integer
samples to float in buffered chunks (0.34–0.84 ns per sample in cache, here); compiled, the same
division (``float32(x) / float32(full_scale)``, correctly rounded, so bit for bit the same values)
is one vectorised loop (~0.26 ns).  With the engine's reused sub-band buffer, the conversion went
from the largest cost of a 2048² PTM fit (39 %) to 0.11 s of CPU (docs/fitting.md "Speed, second
pass: where the time goes now").  Float samples are copied as they are.
"""

from __future__ import annotations

import numba
import numpy as np
import numpy.typing as npt

from lanterna.tiler.inputs.stack import to_unit

from . import compiled  # noqa: F401 - the threading layer, before any kernel runs


@numba.njit(cache=True, nogil=True)
def _divide(src: npt.NDArray[np.integer], full_scale: np.float32,
            out: npt.NDArray[np.float32]) -> None:
    s, o = src.reshape(-1), out.reshape(-1)
    for i in range(s.size):
        o[i] = np.float32(s[i]) / full_scale


def to_unit_compiled(band: npt.NDArray[np.generic], full_scale: float | None,
                     out: npt.NDArray[np.float32]) -> None:
    """:func:`~lanterna.tiler.inputs.stack.to_unit` (the same values), compiled for 8- and
    16-bit ``band`` s; ``out`` is contiguous float32 of ``band``'s shape."""
    if full_scale is None or band.dtype not in (np.uint8, np.uint16) or \
            not out.flags.c_contiguous or out.shape != band.shape:
        to_unit(band, full_scale, out)
        return
    _divide(np.ascontiguousarray(band), np.float32(full_scale), out)
