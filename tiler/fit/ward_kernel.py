"""The α-grid solve of :mod:`.ward_solve`, compiled per pixel (Numba).

numpy evaluates the Ward term of every sample of every pixel at every α of the grid as whole
``(N, b, W)`` arrays (≈ 10 passes over memory per α); compiled, a pixel gathers its valid samples
once (cosi, tan²θh, √(cosi/cosr)) and, per α, accumulates its four sums in registers, skipping
the samples whose lobe value is below e⁻⁵⁰ of the peak (they change no sum in float64).  The
steps and constants are :func:`~lanterna.tiler.fit.ward_solve.solve_ward_band`'s (the
reference, checked in tests/python/fit/test_engine_kernels.py); sums run in another order, so a
pixel whose best α is a near tie may pick the neighbouring grid value.
"""

from __future__ import annotations

import math

import numba
import numpy as np
import numpy.typing as npt

from . import compiled  # noqa: F401 - the threading layer, before any kernel runs
from . import ward_solve as ws

_SQRT3 = 1.0 / math.sqrt(3.0)
_SKIP = 50.0  # exp(-50) ≈ 2e-22: the sample adds nothing to a float64 sum
_CHUNK = 256  # pixels per parallel task, sharing one set of scratch arrays


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
    n, p = raw.shape[0], raw.shape[1]
    for chunk in numba.prange((p + _CHUNK - 1) // _CHUNK):
        q0, q1 = chunk * _CHUNK, min(p, (chunk + 1) * _CHUNK)
        samples = np.empty((q1 - q0, n, 3), np.float32)  # the chunk pixel-major
        for i in range(n):
            for q in range(q0, q1):
                for c in range(3):
                    samples[q - q0, i, c] = raw[i, q, c]
        scratch = np.empty((6, n))  # a, tan², √(cosi/cosr), y_r, y_g, y_b of the valid samples
        for q in range(q0, q1):
            _pixel(samples[q - q0], nrm[q], lights, half, grid, min_cosi, saturated, cos_max,
                   min_lobe, lobe_width, scratch, kd_out[q], ks_out[q], al_out[q:q + 1])


@numba.njit(cache=True, nogil=True)
def _pixel(raw: npt.NDArray[np.float32], nrm: npt.NDArray[np.float64],
           lights: npt.NDArray[np.float64], half: npt.NDArray[np.float64],
           grid: npt.NDArray[np.float64], min_cosi: float, saturated: float, cos_max: float,
           min_lobe: int, lobe_width: float, scratch: npt.NDArray[np.float64],
           kd_out: npt.NDArray[np.float32], ks_out: npt.NDArray[np.float32],
           al_out: npt.NDArray[np.float32]) -> None:
    """One pixel: its samples ``raw (N, 3)`` and normal; writes its kd, ks and α."""
    n = raw.shape[0]
    nx, ny, nz = nrm[0], nrm[1], nrm[2]
    cosr = max(nz, 1e-4)
    av, tv, gv, y0, y1, y2 = (scratch[0], scratch[1], scratch[2], scratch[3], scratch[4],
                              scratch[5])
    m = 0
    saa = say0 = say1 = say2 = yy = 0.0
    for i in range(n):
        cosi = max(lights[i, 0] * nx + lights[i, 1] * ny + lights[i, 2] * nz, 0.0)
        r, g, b = float(raw[i, 0]), float(raw[i, 1]), float(raw[i, 2])
        if cosi < min_cosi or max(r, max(g, b)) >= saturated:
            continue
        nh = max(half[i, 0] * nx + half[i, 1] * ny + half[i, 2] * nz, 1e-4)
        av[m] = cosi
        tv[m] = (1.0 - nh * nh) / (nh * nh)
        gv[m] = math.sqrt(cosi / cosr)
        y0[m], y1[m], y2[m] = r, g, b
        saa += cosi * cosi
        say0 += cosi * r
        say1 += cosi * g
        say2 += cosi * b
        yy += r * r + g * g + b * b
        m += 1
    inv_saa = 1.0 / max(saa, 1e-12)
    kl0, kl1, kl2 = max(say0 * inv_saa, 0.0), max(say1 * inv_saa, 0.0), max(say2 * inv_saa, 0.0)
    norm = math.sqrt(kl0 * kl0 + kl1 * kl1 + kl2 * kl2)
    if norm > 1e-6:
        c0, c1, c2 = kl0 / norm, kl1 / norm, kl2 / norm
    else:
        c0 = c1 = c2 = _SQRT3
    best = np.inf
    bd0 = bd1 = bd2 = bs0 = bs1 = bs2 = 0.0
    al_b = grid[-1]
    for alpha in grid:
        a2 = alpha * alpha
        inv4 = 1.0 / (4.0 * a2)
        qa = 1.0 / a2
        sab = sbb = sby0 = sby1 = sby2 = 0.0
        support = 0
        for j in range(m):
            x = tv[j] * qa
            if x <= lobe_width:
                support += 1
            if x > _SKIP:
                continue
            bw = gv[j] * math.exp(-x) * inv4
            sab += av[j] * bw
            sbb += bw * bw
            sby0 += bw * y0[j]
            sby1 += bw * y1[j]
            sby2 += bw * y2[j]
        det = saa * sbb - sab * sab
        if det > 1e-12 * max(saa * sbb, 1e-30) and support >= min_lobe:
            k0, k1, k2 = _project((saa * sby0 - sab * say0) / det, (saa * sby1 - sab * say1) / det,
                                  (saa * sby2 - sab * say2) / det, c0, c1, c2, cos_max)
            s0, d0 = _channel(min(k0, 1.0), say0, sby0, sab, sbb, inv_saa)
            s1, d1 = _channel(min(k1, 1.0), say1, sby1, sab, sbb, inv_saa)
            s2, d2 = _channel(min(k2, 1.0), say2, sby2, sab, sbb, inv_saa)
        else:
            s0 = s1 = s2 = 0.0
            d0, d1, d2 = kl0, kl1, kl2
        sse = (yy - 2 * (d0 * say0 + s0 * sby0 + d1 * say1 + s1 * sby1 + d2 * say2 + s2 * sby2)
               + (d0 * d0 + d1 * d1 + d2 * d2) * saa + 2 * (d0 * s0 + d1 * s1 + d2 * s2) * sab
               + (s0 * s0 + s1 * s1 + s2 * s2) * sbb)
        if sse < best:
            best = sse
            bd0, bd1, bd2, bs0, bs1, bs2 = d0, d1, d2, s0, s1, s2
            al_b = alpha
    kd_out[0], kd_out[1], kd_out[2] = bd0, bd1, bd2
    ks_out[0], ks_out[1], ks_out[2] = bs0, bs1, bs2
    al_out[0] = al_b


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
