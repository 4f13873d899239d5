"""Settings shared by the compiled (Numba) fit kernels: imported by each kernel module.

The kernels run their ``prange`` loops on Numba's ``workqueue`` threading layer unless
``NUMBA_THREADING_LAYER`` says otherwise: its idle threads wait, where GNU OpenMP's spin
(``GOMP_SPINCOUNT``) — and beside the fit's read-ahead decode thread, on two cores, often shared
with other processes, spinning threads took the cores from the decode (measured: the
photometric stereo of a 1024² 24-light stack 2.6 s with OpenMP, 0.67 s with workqueue, at the
same machine load).  See docs/fitting.md "Speed: where the time goes".
"""

from __future__ import annotations

import os

import numba
import numpy as np
import numpy.typing as npt

if "NUMBA_THREADING_LAYER" not in os.environ:
    numba.config.THREADING_LAYER = "workqueue"  # type: ignore[attr-defined]


def kernel_samples(band: npt.NDArray[np.generic]) -> npt.NDArray[np.generic]:
    """``band`` contiguous for a kernel that divides its samples where it reads them: 8- and
    16-bit kept as decoded, float32 as it is, any other format as float32 (one
    specialisation per sample format, not per caller's dtype)."""
    if band.dtype in (np.uint8, np.uint16):
        return np.ascontiguousarray(band)
    return np.ascontiguousarray(band, np.float32)
