"""The rank-window photometric stereo of :mod:`.normals`, compiled per pixel (Numba).

numpy cannot vectorise a per-pixel selection without sorting, ranking and masking whole
``(P, N)`` arrays several times over; compiled, each pixel is one pass over its N samples in
registers: a stable argsort of its luminances, the rank window ∩ non-shadowed samples (all
non-shadowed ones if fewer than 3), the 3×3 normal equations (ridge 1e-9, solved by Cramer's
rule), ``n = g/|g|`` with ``n_z ≥ 0``, and the per-channel albedo ``Σ w I s / Σ w s²``.  The same
steps as :func:`~lanterna.tiler.fit.normals.solve_normals_band` with ``iterations=0`` (its
reference, checked in tests/python/fit/test_engine_kernels.py); the sums run in another order
and the 3×3 solve is another algorithm, so results agree to float32 rounding, not bit for bit.
Up to :data:`MAX_COUNTED` lights a chunk of pixels runs these steps with the pixels innermost
(:func:`fit_chunk`, vectorised: about half the CPU time of the pixel loop), bit for bit the pixel
loop's results (tests/python/fit/test_fast_paths.py).
"""

from __future__ import annotations

import math

import numba
import numpy as np
import numpy.typing as npt

from .compiled import SAMPLE_TYPES, unit
from .luminance_kernel import luminance_rows

_RIDGE = 1e-9
_CHUNK = 512  # pixels per parallel task
#: The most lights whose ranks are counted (N² comparisons, vectorised across pixels); past it,
#: each pixel sorts its samples.
MAX_COUNTED = 64


@numba.njit(cache=True, parallel=True, nogil=True, error_model="numpy")
def _rank_window(lum: npt.NDArray[np.floating], colour: npt.NDArray[np.generic],
                 lights: npt.NDArray[np.float64], lo: int, hi: int, shadow: float,
                 normals: npt.NDArray[np.float32], albedo: npt.NDArray[np.float32],
                 d: np.float32, weights: npt.NDArray[np.float32], from_colour: bool) -> None:
    n, p = colour.shape[0], colour.shape[1]
    if n <= MAX_COUNTED:  # ranks by counting, vectorised across the chunk's pixels
        for chunk in numba.prange((p + _CHUNK - 1) // _CHUNK):
            q0, q1 = chunk * _CHUNK, min(p, (chunk + 1) * _CHUNK)
            y = chunk_rows(lum, colour, weights, from_colour, q0, q1, d)
            fit_chunk(y, colour, lights, lo, hi, shadow, normals, albedo, q0, d)
        return
    for chunk in numba.prange((p + _CHUNK - 1) // _CHUNK):
        q0, q1 = chunk * _CHUNK, min(p, (chunk + 1) * _CHUNK)
        # the chunk's luminances pixel-major (the input is light-major: a cache line a sample)
        y = chunk_rows(lum, colour, weights, from_colour, q0, q1, d)
        ys = np.empty((q1 - q0, n))
        for i in range(n):
            for q in range(q1 - q0):
                ys[q, i] = y[i, q]
        keep = np.empty(n, np.bool_)
        for q in range(q0, q1):
            _pixel(ys[q - q0], colour, lights, lo, hi, shadow, normals, albedo, q, keep, d)


@numba.njit(cache=True, nogil=True, error_model="numpy")
def chunk_rows(lum: npt.NDArray[np.floating], colour: npt.NDArray[np.generic],
               weights: npt.NDArray[np.float32], from_colour: bool, q0: int, q1: int,
               d: np.float32) -> npt.NDArray[np.generic]:
    """The luminances ``(N, q1 − q0)`` of pixels ``q0:q1``, contiguous rows: ``from_colour``,
    those of ``colour`` (:func:`~.luminance_kernel.luminance_rows`: the luminance kernel's
    values, the band's never stored whole), else a copy of ``lum``'s."""
    if from_colour:
        return luminance_rows(colour, weights, q0, q1, d, lum)
    return chunk_luminance(lum, q0, q1)


@numba.njit(cache=True, nogil=True, error_model="numpy")
def fit_chunk(y: npt.NDArray[np.generic], colour: npt.NDArray[np.generic],
              lights: npt.NDArray[np.float64], lo: int, hi: int, shadow: float,
              normals: npt.NDArray[np.float32], albedo: npt.NDArray[np.float32],
              q0: int, d: np.float32) -> npt.NDArray[np.int32]:
    """Pixels ``q0:q0 + m`` from their luminances ``y (N, m)`` (at most :data:`MAX_COUNTED`
    lights; :func:`chunk_rows`): :func:`_select` and :func:`_pixel`'s arithmetic with every
    loop over the pixels innermost, so it runs on vectors of pixels.  Each pixel's sums add
    the same terms in the same order (a sample left out adds 0.0, which changes no sum), so
    the results are bit for bit those of the pixel loop.  Returns the chunk's ranks
    (:func:`ranks`)."""
    rows = np.arange(y.shape[0])
    rank = ranks(y)
    with_albedo = albedo.shape[0] > 0
    nrm, alb = fit_rows(y, window(y, rank, rows, lo, hi, shadow), rows, lights, colour, q0, d,
                        with_albedo)
    for q in range(y.shape[1]):
        for c in range(3):
            normals[q0 + q, c] = nrm[c, q]
    if with_albedo:
        for q in range(y.shape[1]):
            for c in range(3):
                albedo[q0 + q, c] = alb[c, q]
    return rank


@numba.njit(cache=True, nogil=True, error_model="numpy")
def chunk_luminance(lum: npt.NDArray[np.floating], q0: int, q1: int) -> npt.NDArray[np.generic]:
    """Pixels ``q0:q1`` of ``lum (N, P)``, contiguous rows: the loops over them vectorise."""
    n, m = lum.shape[0], q1 - q0
    y = np.empty((n, m), lum.dtype)
    for i in range(n):
        y[i] = lum[i, q0:q1]
    return y


@numba.njit(cache=True, nogil=True, error_model="numpy")
def ranks(y: npt.NDArray[np.generic]) -> npt.NDArray[np.int32]:
    """``(N, m)``: each sample's stable rank among its pixel's N (earlier equal ones lower)."""
    n, m = y.shape
    rank = np.zeros((n, m), np.int32)
    for i in range(n):
        yi = y[i]
        ri = rank[i]
        for j in range(i):  # earlier equal samples rank lower
            yj = y[j]
            for q in range(m):
                ri[q] += np.int32(yj[q] <= yi[q])
        for j in range(i + 1, n):
            yj = y[j]
            for q in range(m):
                ri[q] += np.int32(yj[q] < yi[q])
    return rank


@numba.njit(cache=True, nogil=True, error_model="numpy")
def window(y: npt.NDArray[np.generic], rank: npt.NDArray[np.int32],
           rows: npt.NDArray[np.intp], lo: int, hi: int, shadow: float
           ) -> npt.NDArray[np.bool_]:
    """``keep (len(rows), m)``: of the samples ``y[rows]`` (``rank`` theirs among them), those
    ranked in ``[lo, hi)`` and brighter than ``shadow`` × their maximum; every such brighter
    one where fewer than 3."""
    n, m = rows.shape[0], y.shape[1]
    threshold = np.empty(m)
    for q in range(m):
        threshold[q] = float(y[rows[0], q])
    for j in range(1, n):
        yj = y[rows[j]]
        for q in range(m):
            threshold[q] = max(threshold[q], float(yj[q]))
    for q in range(m):
        threshold[q] *= shadow
    keep = np.empty((n, m), np.bool_)
    count = np.zeros(m, np.int32)
    for j in range(n):
        yj, rj, kj = y[rows[j]], rank[j], keep[j]
        for q in range(m):
            k = (rj[q] >= lo) & (rj[q] < hi) & (float(yj[q]) > threshold[q])
            kj[q] = k
            count[q] += np.int32(k)
    for j in range(n):
        yj = y[rows[j]]
        for q in range(m):
            if count[q] < 3:
                keep[j, q] = float(yj[q]) > threshold[q]
    return keep


@numba.njit(cache=True, nogil=True, error_model="numpy")
def fit_rows(y: npt.NDArray[np.generic], keep: npt.NDArray[np.bool_],
             rows: npt.NDArray[np.intp], lights: npt.NDArray[np.float64],
             colour: npt.NDArray[np.generic], q0: int, d: np.float32, with_albedo: bool
             ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """Normals and albedo ``(3, m)`` of the kept samples of the lights ``rows`` (summed in
    their order; the albedo ``(3, 0)``, not fitted, unless ``with_albedo``); ``colour (N, P,
    3)`` contiguous, read from pixel ``q0`` (each sample :func:`~.compiled.unit` of ``d``).

    Each loop over the pixels updates at most three sums, each its own array: LLVM vectorises
    a loop only when it can check at run time that its arrays do not overlap, and it gives up
    past a few of them (the nine sums in one loop ran scalar, three times slower).  The
    albedo's sums run over the colour samples in their stored order (pixel-major, the three
    channels interleaved), each shading repeated for its three: the same terms in the same
    order, so the same bits."""
    n, m = rows.shape[0], y.shape[1]
    a = np.zeros((9, m))  # a00 a11 a22 a01 a02 a12 b0 b1 b2
    for part in range(3):
        s0, s1, s2 = a[3 * part], a[3 * part + 1], a[3 * part + 2]
        for j in range(n):
            i = rows[j]
            lx, ly, lz = lights[i, 0], lights[i, 1], lights[i, 2]
            f0, f1, f2 = ((lx * lx, ly * ly, lz * lz) if part == 0 else
                          (lx * ly, lx * lz, ly * lz) if part == 1 else (lx, ly, lz))
            yr, kj = y[i], keep[j]
            for q in range(m):
                k = kj[q]
                yi = float(yr[q]) if part == 2 else 1.0
                s0[q] += yi * f0 if k else 0.0
                s1[q] += yi * f1 if k else 0.0
                s2[q] += yi * f2 if k else 0.0
    nrm = np.empty((3, m))
    for q in range(m):
        g0, g1, g2 = _solve3(a[0, q] + _RIDGE, a[1, q] + _RIDGE, a[2, q] + _RIDGE, a[3, q],
                             a[4, q], a[5, q], a[6, q], a[7, q], a[8, q])
        nrm[0, q], nrm[1, q], nrm[2, q] = _unit(g0, g1, g2)
    if not with_albedo:
        return nrm, np.empty((3, 0))
    den = np.zeros(m)
    shade = np.empty(3 * m)  # each pixel's shading, once per channel
    sums = np.zeros(3 * m)  # Σ s · I per pixel and channel, interleaved as stored
    n0, n1, n2 = nrm[0], nrm[1], nrm[2]
    for j in range(n):
        i = rows[j]
        lx, ly, lz = lights[i, 0], lights[i, 1], lights[i, 2]
        kj = keep[j]
        for q in range(m):
            s = max(0.0, n0[q] * lx + n1[q] * ly + n2[q] * lz) if kj[q] else 0.0
            den[q] += s * s
            shade[3 * q] = s
            shade[3 * q + 1] = s
            shade[3 * q + 2] = s
        c = colour[i].reshape(-1)[3 * q0:3 * (q0 + m)]
        for t in range(3 * m):  # a sample left out (or unlit) adds 0.0, as before
            sums[t] += shade[t] * unit(c[t], d) if shade[t] > 0.0 else 0.0
    alb = np.empty((3, m))
    for q in range(m):
        dd = max(den[q], 1e-12)
        alb[0, q], alb[1, q], alb[2, q] = sums[3 * q] / dd, sums[3 * q + 1] / dd, \
            sums[3 * q + 2] / dd
    return nrm, alb


@numba.njit(cache=True, nogil=True, inline="always", error_model="numpy")
def _solve3(a00: float, a11: float, a22: float, a01: float, a02: float, a12: float,
            b0: float, b1: float, b2: float) -> tuple[float, float, float]:
    """The symmetric 3×3 system by Cramer's rule; ``(0, 0, 0)`` if singular."""
    c00 = a11 * a22 - a12 * a12
    c01 = a02 * a12 - a01 * a22
    c02 = a01 * a12 - a02 * a11
    det = a00 * c00 + a01 * c01 + a02 * c02
    if det == 0.0:
        return 0.0, 0.0, 0.0
    c11 = a00 * a22 - a02 * a02
    c12 = a01 * a02 - a00 * a12
    c22 = a00 * a11 - a01 * a01
    return ((c00 * b0 + c01 * b1 + c02 * b2) / det, (c01 * b0 + c11 * b1 + c12 * b2) / det,
            (c02 * b0 + c12 * b1 + c22 * b2) / det)


@numba.njit(cache=True, nogil=True, inline="always", error_model="numpy")
def _unit(g0: float, g1: float, g2: float) -> tuple[float, float, float]:
    """``g/|g|`` flipped to ``n_z ≥ 0``; ``(0, 0, 1)`` for ``|g|`` ≈ 0."""
    norm = math.sqrt(g0 * g0 + g1 * g1 + g2 * g2)
    if not norm > 1e-12:
        return 0.0, 0.0, 1.0
    nx, ny, nz = g0 / norm, g1 / norm, g2 / norm
    if nz < 0:
        return -nx, -ny, -nz
    return nx, ny, nz


@numba.njit(cache=True, nogil=True, error_model="numpy")
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


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _pixel(y: npt.NDArray[np.float64], colour: npt.NDArray[np.generic],
           lights: npt.NDArray[np.float64], lo: int, hi: int, shadow: float,
           normals: npt.NDArray[np.float32], albedo: npt.NDArray[np.float32], q: int,
           keep: npt.NDArray[np.bool_], d: np.float32) -> None:
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
    g0, g1, g2 = _solve3(a00 + _RIDGE, a11 + _RIDGE, a22 + _RIDGE, a01, a02, a12, b0, b1, b2)
    nx, ny, nz = _unit(g0, g1, g2)
    normals[q, 0], normals[q, 1], normals[q, 2] = nx, ny, nz
    if albedo.shape[0] == 0:  # not fitted
        return
    den = 0.0
    r0 = r1 = r2 = 0.0
    for i in range(n):
        if keep[i]:
            s = max(0.0, nx * lights[i, 0] + ny * lights[i, 1] + nz * lights[i, 2])
            den += s * s
            r0 += s * unit(colour[i, q, 0], d)
            r1 += s * unit(colour[i, q, 1], d)
            r2 += s * unit(colour[i, q, 2], d)
    den = max(den, 1e-12)
    albedo[q, 0], albedo[q, 1], albedo[q, 2] = r0 / den, r1 / den, r2 / den


def rank_window_normals(lum: npt.NDArray[np.floating] | None, colour: npt.NDArray[np.generic],
                        lights: npt.NDArray[np.float64], lo: int, hi: int, shadow: float,
                        div: float = 1.0, weights: npt.NDArray[np.float32] | None = None,
                        albedo: bool = True
                        ) -> tuple[npt.NDArray[np.float32], npt.NDArray[np.float32]]:
    """Normals and albedo ``(P, 3)`` float32 of ``lum (N, P)``, ``colour (N, P, 3)`` (float32
    or float64, or 8-/16-bit as decoded with ``div`` 255/65535: compiled for each) under unit
    ``lights (N, 3)``, from the samples ranked ``[lo, hi)`` and brighter than ``shadow`` × the
    pixel's maximum (checked by the caller).  ``lum`` None: the float32 luminance of ``colour``
    (float32 or 8-/16-bit) with ``weights``, taken chunk by chunk inside the kernel (the
    values of :func:`~.luminance_kernel.luminance_compiled`, so the same results).
    ``albedo`` False: the albedo is not fitted (returned ``(0, 3)``; the normals the same)."""
    p = colour.shape[1]
    normals = np.empty((p, 3), np.float32)
    rho = np.empty((p if albedo else 0, 3), np.float32)
    rows, w = kernel_rows(lum, colour, weights)
    _rank_window(rows, np.ascontiguousarray(colour), np.ascontiguousarray(lights, np.float64),
                 lo, hi, float(shadow), normals, rho, np.float32(div), w, lum is None)
    return normals, rho


def kernel_rows(lum: npt.NDArray[np.floating] | None, colour: npt.NDArray[np.generic],
                weights: npt.NDArray[np.float32] | None
                ) -> tuple[npt.NDArray[np.floating], npt.NDArray[np.float32]]:
    """The kernels' ``lum`` and ``weights``: ``lum`` contiguous; or (None) an empty float32
    stand-in, the luminances then taken from ``colour`` with ``weights``."""
    if lum is not None:
        return np.ascontiguousarray(lum), np.zeros(3, np.float32)
    if weights is None or colour.dtype not in SAMPLE_TYPES:
        raise ValueError("the luminance is taken from a float32 or 8-/16-bit colour, with "
                         "its weights")
    return np.empty((colour.shape[0], 0), np.float32), np.asarray(weights, np.float32)
