"""Settings shared by the compiled (Numba) fit kernels: imported by each kernel module.

The kernels run their ``prange`` loops on Numba's ``workqueue`` threading layer unless
``NUMBA_THREADING_LAYER`` says otherwise: its idle threads wait, where GNU OpenMP's spin
(``GOMP_SPINCOUNT``) — and beside the fit's read-ahead decode thread, on two cores, often shared
with other processes, spinning threads took the cores from the decode (measured: the
photometric stereo of a 1024² 24-light stack 2.6 s with OpenMP, 0.67 s with workqueue, at the
same machine load).  See docs/fitting.md "Speed: where the time goes".  On a CPU with AVX-512
they are built for 512-bit vectors unless ``NUMBA_CPU_FEATURES`` or ``NUMBA_CPU_NAME`` says
otherwise (:func:`_wide_vectors`).
"""

from __future__ import annotations

import os
from typing import Any

import numba
import numpy as np
import numpy.typing as npt
from llvmlite import binding as llvm
from numba import types
from numba.extending import overload

if "NUMBA_THREADING_LAYER" not in os.environ:
    numba.config.THREADING_LAYER = "workqueue"  # type: ignore[attr-defined]


def _wide_vectors(features: str) -> str | None:
    """The host's features with LLVM's preference for 256-bit vectors lifted, on a CPU with
    AVX-512 (else ``None``: numba's default).  LLVM prefers 256 bits on AVX-512 CPUs (older
    ones slowed their clock for 512-bit code); our kernels' loops are independent lanes, so
    512 bits means half the instructions: measured on this machine (a Rocket Lake Xeon), the Ward
    kernel 24 % faster, the normals fit 7–25 %, PTM/HSH/RBF fits 2–3 %, none slower beyond
    noise.  A wider vector changes no result: no kernel vectorises a floating-point sum
    across its terms (numba's default math, without reassociation)."""
    return features + ",-prefer-256-bit" if "+avx512f" in features.split(",") else None


if "NUMBA_CPU_FEATURES" not in os.environ and "NUMBA_CPU_NAME" not in os.environ:
    numba.config.CPU_FEATURES = _wide_vectors(  # type: ignore[attr-defined]
        llvm.get_host_cpu_features().flatten())


#: The sample types the kernels read as they are (8-/16-bit as decoded, with :func:`unit`).
SAMPLE_TYPES = (np.float32, np.uint8, np.uint16)


def kernel_samples(band: npt.NDArray[np.generic]) -> npt.NDArray[np.generic]:
    """``band`` contiguous for a kernel that divides its samples where it reads them: 8- and
    16-bit kept as decoded, float32 as it is, any other format as float32 (one
    specialisation per sample format, not per caller's dtype)."""
    if band.dtype in (np.uint8, np.uint16):
        return np.ascontiguousarray(band)
    return np.ascontiguousarray(band, np.float32)


def unit(x: Any, d: np.float32) -> Any:
    """A sample in 0–1 inside a kernel: an 8-/16-bit ``x`` as ``float32(x) / d`` (the
    values of :func:`~lanterna.tiler.inputs.stack.to_unit`, bit for bit), a float one as it is
    (``d`` unused).  So a kernel reads a band as decoded, or as floats, with the same results."""
    raise NotImplementedError("unit() is only called inside compiled kernels")


@overload(unit, inline="always")
def _unit(x, d):  # type: ignore[no-untyped-def]  # numba matches it to the stand-in's names
    if isinstance(x, types.Integer):
        return lambda x, d: np.float32(x) / d
    return lambda x, d: x
