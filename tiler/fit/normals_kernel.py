"""The rank-window photometric stereo of :mod:`.normals`, compiled per pixel (Numba).

numpy cannot vectorise a per-pixel selection without sorting, ranking and masking whole
``(P, N)`` arrays several times over; compiled, each pixel is one pass over its N samples in
registers: a stable argsort of its luminances, the rank window ∩ non-shadowed samples (all
non-shadowed ones if fewer than 3), the 3×3 normal equations (ridge 1e-9, solved by Cramer's
rule), ``n = g/|g|`` with ``n_z ≥ 0``, and the per-channel albedo ``Σ w I s / Σ w s²``.  The same
steps as :func:`~lanterna.tiler.fit.normals.solve_normals_band` with ``iterations=0`` (its
reference, checked in tests/python/fit/test_normals_kernel.py); the sums run in another order
and the 3×3 solve is another algorithm, so results agree to float32 rounding, not bit for bit.
"""

from __future__ import annotations

import math

import numba
import numpy as np
import numpy.typing as npt

from . import compiled  # noqa: F401 - the threading layer, before any kernel runs

_RIDGE = 1e-9
_CHUNK = 512  # pixels per parallel task


@numba.njit(cache=True, parallel=True, nogil=True)
def _rank_window(lum: npt.NDArray[np.floating], colour: npt.NDArray[np.floating],
                 lights: npt.NDArray[np.float64], lo: int, hi: int, shadow: float,
                 normals: npt.NDArray[np.float32], albedo: npt.NDArray[np.float32]) -> None:
    n, p = lum.shape
    for chunk in numba.prange((p + _CHUNK - 1) // _CHUNK):
        q0, q1 = chunk * _CHUNK, min(p, (chunk + 1) * _CHUNK)
        # the chunk's luminances pixel-major (the input is light-major: a cache line a sample)
        ys = np.empty((q1 - q0, n))
        for i in range(n):
            for q in range(q0, q1):
                ys[q - q0, i] = lum[i, q]
        keep = np.empty(n, np.bool_)
        for q in range(q0, q1):
            _pixel(ys[q - q0], colour, lights, lo, hi, shadow, normals, albedo, q, keep)


@numba.njit(cache=True, nogil=True)
def _select(y: npt.NDArray[np.float64], lo: int, hi: int, shadow: float,
            keep: npt.NDArray[np.bool_]) -> None:
    """``keep`` = the samples whose stable rank is in ``[lo, hi)`` and brighter than ``shadow``
    × the maximum; every such brighter sample if fewer than 3."""
    n = y.shape[0]
    threshold = shadow * y.max()
    count = 0
    if n <= 64:  # ranks by counting: branch-free, no sort
        for i in range(n):
            yi = y[i]
            rank = 0
            for j in range(i):  # earlier equal samples rank lower
                rank += 1 if y[j] <= yi else 0
            for j in range(i + 1, n):
                rank += 1 if y[j] < yi else 0
            keep[i] = (rank >= lo) & (rank < hi) & (yi > threshold)
            count += keep[i]
    else:
        keep[:] = False
        order = np.argsort(y, kind="mergesort")  # stable: ties ranked by position
        for r in range(lo, min(hi, n)):
            i = order[r]
            if y[i] > threshold:
                keep[i] = True
                count += 1
    if count < 3:
        for i in range(n):
            keep[i] = y[i] > threshold


@numba.njit(cache=True, nogil=True)
def _pixel(y: npt.NDArray[np.float64], colour: npt.NDArray[np.floating],
           lights: npt.NDArray[np.float64], lo: int, hi: int, shadow: float,
           normals: npt.NDArray[np.float32], albedo: npt.NDArray[np.float32], q: int,
           keep: npt.NDArray[np.bool_]) -> None:
    """Pixel ``q``: its luminances ``y (N,)``; writes row ``q`` of the outputs."""
    n = y.shape[0]
    _select(y, lo, hi, shadow, keep)
    a00 = a11 = a22 = a01 = a02 = a12 = 0.0
    b0 = b1 = b2 = 0.0
    for i in range(n):
        if keep[i]:
            lx, ly, lz = lights[i, 0], lights[i, 1], lights[i, 2]
            a00 += lx * lx
            a11 += ly * ly
            a22 += lz * lz
            a01 += lx * ly
            a02 += lx * lz
            a12 += ly * lz
            b0 += y[i] * lx
            b1 += y[i] * ly
            b2 += y[i] * lz
    a00 += _RIDGE
    a11 += _RIDGE
    a22 += _RIDGE
    c00 = a11 * a22 - a12 * a12
    c01 = a02 * a12 - a01 * a22
    c02 = a01 * a12 - a02 * a11
    det = a00 * c00 + a01 * c01 + a02 * c02
    g0 = g1 = g2 = 0.0
    if det != 0.0:
        c11 = a00 * a22 - a02 * a02
        c12 = a01 * a02 - a00 * a12
        c22 = a00 * a11 - a01 * a01
        g0 = (c00 * b0 + c01 * b1 + c02 * b2) / det
        g1 = (c01 * b0 + c11 * b1 + c12 * b2) / det
        g2 = (c02 * b0 + c12 * b1 + c22 * b2) / det
    norm = math.sqrt(g0 * g0 + g1 * g1 + g2 * g2)
    if norm > 1e-12:
        nx, ny, nz = g0 / norm, g1 / norm, g2 / norm
    else:
        nx, ny, nz = 0.0, 0.0, 1.0
    if nz < 0:
        nx, ny, nz = -nx, -ny, -nz
    normals[q, 0], normals[q, 1], normals[q, 2] = nx, ny, nz
    den = 0.0
    r0 = r1 = r2 = 0.0
    for i in range(n):
        if keep[i]:
            s = max(0.0, nx * lights[i, 0] + ny * lights[i, 1] + nz * lights[i, 2])
            den += s * s
            r0 += s * colour[i, q, 0]
            r1 += s * colour[i, q, 1]
            r2 += s * colour[i, q, 2]
    den = max(den, 1e-12)
    albedo[q, 0], albedo[q, 1], albedo[q, 2] = r0 / den, r1 / den, r2 / den


def rank_window_normals(lum: npt.NDArray[np.floating], colour: npt.NDArray[np.floating],
                        lights: npt.NDArray[np.float64], lo: int, hi: int, shadow: float
                        ) -> tuple[npt.NDArray[np.float32], npt.NDArray[np.float32]]:
    """Normals and albedo ``(P, 3)`` float32 of ``lum (N, P)``, ``colour (N, P, 3)`` (float32
    or float64: compiled for each) under unit ``lights (N, 3)``, from the samples ranked
    ``[lo, hi)`` and brighter than ``shadow`` × the pixel's maximum (checked by the caller)."""
    p = lum.shape[1]
    normals = np.empty((p, 3), np.float32)
    albedo = np.empty((p, 3), np.float32)
    _rank_window(np.ascontiguousarray(lum), np.ascontiguousarray(colour),
                 np.ascontiguousarray(lights, np.float64), lo, hi, float(shadow), normals, albedo)
    return normals, albedo
