"""The α-grid solve of :mod:`.ward_solve`, compiled (Numba).

numpy evaluates the Ward term of every sample of every pixel at every α of the grid as whole
``(N, b, W)`` arrays (≈ 10 passes over memory per α).  Compiled, the pixels are solved
:data:`_LANES` side by side, one parallel task per group: each pixel's samples are gathered once
(cosi, tan²θh, √(cosi/cosr), colour; an excluded sample kept as one that adds exactly 0), then
per α one loop over the lanes, branch-free and with :func:`~.exp_kernel.exp_neg` instead of
libm's ``exp``, so it vectorises, sums each pixel's samples in light order; and each pixel's
constrained 2×2 solve at that α keeps the best α so far.  A sample whose lobe value is below
e⁻⁵⁰ of the peak adds 0 (as skipped: it changes no float64 sum).  The steps and constants are
:func:`~lanterna.tiler.fit.ward_solve.solve_ward_band`'s (the reference, checked in
tests/python/fit/test_engine_kernels.py); sums run in another order, so a pixel whose best α is
a near tie may pick the neighbouring grid value.
"""

from __future__ import annotations

import math

import numba
import numpy as np
import numpy.typing as npt

from . import compiled  # noqa: F401 - the threading layer, before any kernel runs
from . import ward_solve as ws
from .exp_kernel import exp_neg

_SQRT3 = 1.0 / math.sqrt(3.0)
_SKIP = 50.0  # exp(-50) ≈ 2e-22: the sample adds nothing to a float64 sum
_LANES = 32  # pixels solved side by side: one parallel task, one vectorised loop
_STATS = 12  # Σaa, Σay (r, g, b), Σyy, 1/Σaa, Lambert-only kd (r, g, b), its chroma


@numba.njit(cache=True, nogil=True)
def _project(k0: float, k1: float, k2: float, c0: float, c1: float, c2: float,
             cos_max: float) -> tuple[float, float, float]:
    """:func:`~.ward_solve.constrain_specular` of one ks colour (chroma unit, ≥ 0)."""
    c = (c0 + c1 + c2) * _SQRT3
    xg = (k0 + k1 + k2) * _SQRT3
    xc = k0 * c0 + k1 * c1 + k2 * c2
    span = 1.0 - c * c
    u = v = 0.0
    inside = False
    if span > 1e-9:
        u = (xg - c * xc) / span
        v = (xc - c * xg) / span
        inside = u >= 0 and v >= 0
    if not inside:
        pg = max(xg, 0.0)
        pc = max(xc, 0.0) if span > 1e-9 else 0.0
        if pc > pg:
            u, v = 0.0, pc
        else:
            u, v = pg, 0.0
    p0 = u * _SQRT3 + v * c0
    p1 = u * _SQRT3 + v * c1
    p2 = u * _SQRT3 + v * c2
    f0, f1, f2 = max(k0, 0.0), max(k1, 0.0), max(k2, 0.0)
    dot = f0 * p0 + f1 * p1 + f2 * p2
    nf = math.sqrt(f0 * f0 + f1 * f1 + f2 * f2)
    nc = math.sqrt(p0 * p0 + p1 * p1 + p2 * p2)
    if nc > 0 and dot >= cos_max * nf * nc:
        return f0, f1, f2
    return p0, p1, p2


@numba.njit(cache=True, parallel=True, nogil=True)
def _ward(raw: npt.NDArray[np.float32], nrm: npt.NDArray[np.float64],
          lights: npt.NDArray[np.float64], half: npt.NDArray[np.float64],
          grid: npt.NDArray[np.float64], min_cosi: float, saturated: float, cos_max: float,
          min_lobe: int, lobe_width: float, kd_out: npt.NDArray[np.float32],
          ks_out: npt.NDArray[np.float32], al_out: npt.NDArray[np.float32]) -> None:
    n, p, nk = raw.shape[0], raw.shape[1], grid.shape[0]
    qa = 1.0 / (grid * grid)
    inv4 = 1.0 / (4.0 * (grid * grid))
    for block in numba.prange((p + _LANES - 1) // _LANES):
        q0 = block * _LANES
        lanes = min(p, q0 + _LANES) - q0
        samples = np.empty((6, n, lanes))
        stats = np.empty((_STATS, lanes))
        sums = np.empty((6, lanes))
        best = np.empty((8, lanes))  # SSE, kd (r, g, b), ks (r, g, b), α of the best α so far
        best[0] = np.inf
        best[1:7] = 0.0
        best[7] = grid[-1]
        for q in range(lanes):
            _samples(raw, q0 + q, nrm[q0 + q], lights, half, min_cosi, saturated, samples,
                     stats, q)
        nearest = np.empty(n)  # per light, the smallest tan²θh of the lanes
        for i in range(n):
            nearest[i] = samples[1, i].min()
        for k in range(nk):
            _sums(samples, nearest, qa[k], inv4[k], lobe_width, sums)
            for q in range(lanes):
                _try_alpha(stats, sums, q, grid[k], cos_max, min_lobe, best)
        for q in range(lanes):
            for c in range(3):
                kd_out[q0 + q, c] = best[1 + c, q]
                ks_out[q0 + q, c] = best[4 + c, q]
            al_out[q0 + q] = best[7, q]


@numba.njit(cache=True, nogil=True)
def _samples(raw: npt.NDArray[np.float32], px: int, nrm: npt.NDArray[np.float64],
             lights: npt.NDArray[np.float64], half: npt.NDArray[np.float64], min_cosi: float,
             saturated: float, samples: npt.NDArray[np.float64],
             stats: npt.NDArray[np.float64], q: int) -> None:
    """Lane ``q`` of ``samples``: pixel ``px``'s cosi, tan²θh, √(cosi/cosr) and colour per
    light, an excluded sample as one that adds nothing (tan²θh = ∞, the rest 0); and its
    ``stats``: Σaa, Σay (r, g, b), Σyy, 1/Σaa, the Lambert-only kd and its chroma."""
    n = raw.shape[0]
    nx, ny, nz = nrm[0], nrm[1], nrm[2]
    cosr = max(nz, 1e-4)
    saa = say0 = say1 = say2 = yy = 0.0
    for i in range(n):
        cosi = max(lights[i, 0] * nx + lights[i, 1] * ny + lights[i, 2] * nz, 0.0)
        r, g, b = float(raw[i, px, 0]), float(raw[i, px, 1]), float(raw[i, px, 2])
        if cosi < min_cosi or max(r, max(g, b)) >= saturated:
            samples[0, i, q] = 0.0
            samples[1, i, q] = np.inf
            for c in range(2, 6):
                samples[c, i, q] = 0.0
            continue
        nh = max(half[i, 0] * nx + half[i, 1] * ny + half[i, 2] * nz, 1e-4)
        samples[0, i, q] = cosi
        samples[1, i, q] = (1.0 - nh * nh) / (nh * nh)
        samples[2, i, q] = math.sqrt(cosi / cosr)
        samples[3, i, q], samples[4, i, q], samples[5, i, q] = r, g, b
        saa += cosi * cosi
        say0 += cosi * r
        say1 += cosi * g
        say2 += cosi * b
        yy += r * r + g * g + b * b
    inv_saa = 1.0 / max(saa, 1e-12)
    kl0, kl1, kl2 = max(say0 * inv_saa, 0.0), max(say1 * inv_saa, 0.0), max(say2 * inv_saa, 0.0)
    norm = math.sqrt(kl0 * kl0 + kl1 * kl1 + kl2 * kl2)
    if norm > 1e-6:
        c0, c1, c2 = kl0 / norm, kl1 / norm, kl2 / norm
    else:
        c0 = c1 = c2 = _SQRT3
    for c, v in enumerate((saa, say0, say1, say2, yy, inv_saa, kl0, kl1, kl2, c0, c1, c2)):
        stats[c, q] = v


@numba.njit(cache=True, nogil=True)
def _sums(samples: npt.NDArray[np.float64], nearest: npt.NDArray[np.float64], qa: float,
          inv4: float, lobe_width: float, sums: npt.NDArray[np.float64]) -> None:
    """Per lane at one α: Σab, Σbb, Σby (r, g, b) over the samples in light order, and the
    number of samples inside the lobe.  Branch-free over the lanes, so the loop vectorises
    (a sample with x > :data:`_SKIP` adds an exact 0, as if skipped); a light whose smallest
    tan²θh over the lanes (``nearest``) puts every lane past :data:`_SKIP` is skipped whole."""
    sums[:] = 0.0
    lanes = sums.shape[1]
    for i in range(samples.shape[1]):
        if nearest[i] * qa > _SKIP:
            continue
        for q in range(lanes):
            x = samples[1, i, q] * qa
            sums[5, q] += 1.0 if x <= lobe_width else 0.0
            # both sides of the select run: min() keeps exp_neg's argument in its range
            bw = samples[2, i, q] * exp_neg(min(x, _SKIP)) * inv4 if x <= _SKIP else 0.0
            sums[0, q] += samples[0, i, q] * bw
            sums[1, q] += bw * bw
            sums[2, q] += bw * samples[3, i, q]
            sums[3, q] += bw * samples[4, i, q]
            sums[4, q] += bw * samples[5, i, q]


@numba.njit(cache=True, nogil=True, inline="always")
def _try_alpha(st: npt.NDArray[np.float64], sm: npt.NDArray[np.float64], q: int, alpha: float,
               cos_max: float, min_lobe: int, best: npt.NDArray[np.float64]) -> None:
    """Lane ``q``'s constrained solve at ``alpha`` from its ``stats`` and ``sums``; kept in
    ``best`` if its SSE is the smallest so far."""
    saa, say0, say1, say2, yy, inv_saa = st[0, q], st[1, q], st[2, q], st[3, q], st[4, q], st[5, q]
    sab, sbb, sby0, sby1, sby2 = sm[0, q], sm[1, q], sm[2, q], sm[3, q], sm[4, q]
    det = saa * sbb - sab * sab
    if det > 1e-12 * max(saa * sbb, 1e-30) and sm[5, q] >= min_lobe:
        k0, k1, k2 = _project((saa * sby0 - sab * say0) / det, (saa * sby1 - sab * say1) / det,
                              (saa * sby2 - sab * say2) / det, st[9, q], st[10, q], st[11, q],
                              cos_max)
        s0, d0 = _channel(min(k0, 1.0), say0, sby0, sab, sbb, inv_saa)
        s1, d1 = _channel(min(k1, 1.0), say1, sby1, sab, sbb, inv_saa)
        s2, d2 = _channel(min(k2, 1.0), say2, sby2, sab, sbb, inv_saa)
    else:
        s0 = s1 = s2 = 0.0
        d0, d1, d2 = st[6, q], st[7, q], st[8, q]
    sse = (yy - 2 * (d0 * say0 + s0 * sby0 + d1 * say1 + s1 * sby1 + d2 * say2 + s2 * sby2)
           + (d0 * d0 + d1 * d1 + d2 * d2) * saa + 2 * (d0 * s0 + d1 * s1 + d2 * s2) * sab
           + (s0 * s0 + s1 * s1 + s2 * s2) * sbb)
    if sse < best[0, q]:
        best[0, q], best[1, q], best[2, q], best[3, q] = sse, d0, d1, d2
        best[4, q], best[5, q], best[6, q], best[7, q] = s0, s1, s2, alpha


@numba.njit(cache=True, nogil=True, inline="always")
def _channel(ks: float, say: float, sby: float, sab: float, sbb: float,
             inv_saa: float) -> tuple[float, float]:
    """``(ks, kd)`` of one channel: kd refitted for ks; kd < 0 → kd = 0 and ks alone (capped)."""
    kd_raw = (say - sab * ks) * inv_saa
    if kd_raw < 0:
        return min(max(sby / max(sbb, 1e-30), 0.0), 1.0), 0.0
    return ks, kd_raw


def ward_band_compiled(raw: npt.NDArray[np.float32], nrm: npt.NDArray[np.floating],
                       lights: npt.NDArray[np.float64], grid: npt.NDArray[np.float64]
                       ) -> tuple[npt.NDArray[np.float32], npt.NDArray[np.float32],
                                  npt.NDArray[np.float32]]:
    """:func:`~.ward_solve.solve_ward_band` of ``raw (N, b, W, 3)``, ``nrm (b, W, 3)``:
    kd, ks ``(b, W, 3)`` and α ``(b, W)`` float32, with the constants read at call time."""
    n, b, w, _ = raw.shape
    lf = np.ascontiguousarray(lights, np.float64)
    half = lf + np.array([0.0, 0.0, 1.0])
    half /= np.maximum(np.linalg.norm(half, axis=1, keepdims=True), 1e-12)
    kd = np.empty((b * w, 3), np.float32)
    ks = np.empty((b * w, 3), np.float32)
    al = np.empty(b * w, np.float32)
    _ward(np.ascontiguousarray(raw, np.float32).reshape(n, b * w, 3),
          np.ascontiguousarray(nrm, np.float64).reshape(b * w, 3), lf, half,
          np.ascontiguousarray(grid, np.float64), ws.MIN_COSI, ws.SATURATED,
          math.cos(math.radians(ws.MAX_SPECULAR_ANGLE)), ws.MIN_LOBE_SAMPLES, ws.LOBE_WIDTH,
          kd, ks, al)
    return kd.reshape(b, w, 3), ks.reshape(b, w, 3), al.reshape(b, w)
