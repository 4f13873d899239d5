"""The leave-one-out twin's pixels of a band (:func:`~.held_out.report_sample`), compiled.

numpy hashes every pixel of a band in whole-array passes (a temporary per step of SplitMix64):
2.6 ms for a band of 85 rows of 2048 px, and 0.07 s of a 2048² Ward fit with its report, in
the solving thread.  Compiled, each pixel's hash is a few integer operations in registers, and
the pixels kept come out as their indices (what the gather takes), the same ones.
"""

from __future__ import annotations

import numba
import numpy as np
import numpy.typing as npt

from . import compiled  # noqa: F401 - the threading layer, before any kernel runs
from .held_out import SPLITMIX_GAMMA, SPLITMIX_MUL1, SPLITMIX_MUL2, sample_threshold

_GAMMA, _MUL1, _MUL2 = np.uint64(SPLITMIX_GAMMA), np.uint64(SPLITMIX_MUL1), np.uint64(SPLITMIX_MUL2)


@numba.njit(cache=True, nogil=True)
def _indices(y0: int, rows: int, width: int, threshold: np.uint64) -> npt.NDArray[np.intp]:
    out = np.empty(rows * width, np.intp)
    kept = 0
    base = np.uint64(y0) * np.uint64(width)
    for j in range(rows * width):
        z = (base + np.uint64(j) + np.uint64(1)) * _GAMMA
        z = (z ^ (z >> np.uint64(30))) * _MUL1
        z = (z ^ (z >> np.uint64(27))) * _MUL2
        z ^= z >> np.uint64(31)
        if (z >> np.uint64(11)) < threshold:
            out[kept] = j
            kept += 1
    return out[:kept]


def report_indices(y0: int, rows: int, width: int, share: float) -> npt.NDArray[np.intp]:
    """The flat indices ``y·width + x`` (from row ``y0``) of the pixels of rows
    ``y0 … y0 + rows`` in the twin's sample: ``np.flatnonzero(report_sample(...))``."""
    return _indices(int(y0), int(rows), int(width), np.uint64(sample_threshold(share)))
