"""The α search of :mod:`.ward_solve`, compiled (Numba).

numpy evaluates the Ward term of every sample of every pixel at every α as whole ``(N, b, W)``
arrays (≈ 10 passes over memory per α).  Compiled, the pixels are solved :data:`LANES` side by
side, 64 such blocks a parallel task, in flat ``[quantity, lane]`` arrays with a fixed lane
count, so every loop over the lanes is branch-free and vectorises: each pixel's samples are
gathered once here (cosi, tan²θh, √(cosi/cosr), colour; an excluded sample, a padding lane or
light, kept as one that adds exactly 0), with its Lambert-only statistics; then the coarse and
fine passes of :mod:`.ward_search`, and the solve at the stored gloss level.  The steps and
constants are :func:`~lanterna.tiler.fit.ward_solve.solve_ward_band`'s (the reference, checked
in tests/python/fit/test_engine_kernels.py); sums run in another order, so a pixel whose best
α is a near tie may pick the neighbouring grid value.
"""

from __future__ import annotations

import math

import numba
import numpy as np
import numpy.typing as npt

from . import compiled
from . import ward_solve as ws
from .compiled import unit
from .ward_search import GROUP, LANES, refine, search, solve, sums_at

_SQRT3 = 1.0 / math.sqrt(3.0)
_CHUNK = 64  # blocks per parallel task (their scratch allocated once)
#: Σaa, Σay (r, g, b), Σyy, 1/Σaa, Lambert-only kd (r, g, b), its chroma (r, g, b), the chroma's
#: cosine with grey, 1/(1 − that²) (0 where the cone is a ray)
_STATS = 14


@numba.njit(cache=True, parallel=True, nogil=True)
def _ward(raw: npt.NDArray[np.generic], nrm: npt.NDArray[np.floating],
          lights: npt.NDArray[np.float64], half: npt.NDArray[np.float64],
          grid: npt.NDArray[np.float64], qf: npt.NDArray[np.float64],
          coarse: npt.NDArray[np.intp], is_coarse: npt.NDArray[np.bool_],
          qa: npt.NDArray[np.float64], twice: npt.NDArray[np.bool_],
          narrowing: npt.NDArray[np.bool_], stride: int, min_cosi: float,
          saturated: float, cos_max: float, min_lobe: int, lobe_width: float, lo: float, hi: float,
          kd_out: npt.NDArray[np.float32],
          ks_out: npt.NDArray[np.float32], al_out: npt.NDArray[np.float32], d: np.float32
          ) -> None:
    n, p = raw.shape[0], raw.shape[1]
    ng = -(-n // GROUP) * GROUP  # lights padded to whole groups
    inv4 = qa * 0.25
    blocks = (p + LANES - 1) // LANES
    for chunk in numba.prange((blocks + _CHUNK - 1) // _CHUNK):
        # a chunk's scratch, allocated once: for each block every part is written before it
        # is read (zeroing it per block was a memset of 54 KB per 32 pixels)
        samples = np.zeros(ng * 6 * LANES)  # [light, quantity, lane], padded ones add 0
        stats = np.zeros(_STATS * LANES)
        sums = np.empty(6 * LANES)
        # SSE, kd (r, g, b), ks (r, g, b), α, its grid index, of the best α so far
        best = np.empty(9 * LANES)
        steps = np.empty(3 * LANES)  # per lane: α, tried, grid index
        centre = np.empty(LANES, np.intp)
        way = np.empty(LANES, np.intp)
        nearest = np.empty(ng)  # per light, the smallest tan²θh of the lanes
        lobes = np.zeros(ng * LANES)  # the coarse pass's last lobes, squared for the next
        qs = np.empty(LANES)
        for block in range(chunk * _CHUNK, min(blocks, (chunk + 1) * _CHUNK)):
            q0 = block * LANES
            lanes = min(p, q0 + LANES) - q0
            _samples(raw, q0, lanes, nrm, lights, half, min_cosi, saturated, samples, stats, d)
            for i in range(ng):
                row = samples[(i * 6 + 1) * LANES:(i * 6 + 2) * LANES]
                if i >= n:  # a padding light (_samples wrote the lights, padding lanes excluded)
                    row[:] = np.inf
                nearest[i] = row.min()
            search(samples, stats, nearest, grid, coarse, qa, inv4, twice, narrowing, cos_max,
                    min_lobe, lobe_width, sums, lobes, best, steps)
            refine(samples, stats, grid, qf, is_coarse, stride, cos_max, min_lobe, lobe_width,
                    sums, best, steps, qs, centre, way)
            # the best α as its gloss level's, and kd, ks solved again there where ks > 0
            for q in range(LANES):
                level = min(max(np.rint((best[7 * LANES + q] - lo) / (hi - lo) * 255.0), 0.0),
                            255.0)
                alpha = lo + level / 255.0 * (hi - lo)
                best[7 * LANES + q] = alpha
                qs[q] = 1.0 / (alpha * alpha)
                steps[q], steps[LANES + q] = alpha, 1.0
            sums_at(samples, qs, lobe_width, sums)
            solve(stats, sums, steps, cos_max, 0, best, True)
            for q in range(lanes):
                for c in range(3):
                    kd_out[q0 + q, c] = best[(1 + c) * LANES + q]
                    ks_out[q0 + q, c] = best[(4 + c) * LANES + q]
                al_out[q0 + q] = best[7 * LANES + q]


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _samples(raw: npt.NDArray[np.generic], q0: int, lanes: int, nrm: npt.NDArray[np.floating],
             lights: npt.NDArray[np.float64], half: npt.NDArray[np.float64], min_cosi: float,
             saturated: float, samples: npt.NDArray[np.float64],
             stats: npt.NDArray[np.float64], d: np.float32) -> None:
    """Pixels ``q0 …`` as the ``lanes`` first lanes of ``samples``: cosi, tan²θh, √(cosi/cosr)
    and colour per light, an excluded sample (a padding lane's too) as one that adds nothing
    (tan²θh = ∞, the rest 0); and their ``stats``: Σaa, Σay (r, g, b), Σyy, 1/Σaa, the
    Lambert-only kd and its chroma.  Light by light, branch-free over the lanes (so the loop,
    its square root and division included, vectorises); each lane's sums in light order, an
    excluded sample adding an exact 0."""
    L = LANES
    n = raw.shape[0]
    nx, ny, nz = np.zeros(L), np.zeros(L), np.zeros(L)
    for q in range(lanes):
        nx[q], ny[q], nz[q] = nrm[q0 + q, 0], nrm[q0 + q, 1], nrm[q0 + q, 2]
    cosr = np.maximum(nz, 1e-4)
    col = np.zeros(3 * L)
    acc = np.zeros(5 * L)  # Σaa, Σay (r, g, b), Σyy
    for i in range(n):
        for q in range(lanes):
            col[q], col[L + q] = unit(raw[i, q0 + q, 0], d), unit(raw[i, q0 + q, 1], d)
            col[2 * L + q] = unit(raw[i, q0 + q, 2], d)
        row = samples[i * 6 * L:(i + 1) * 6 * L]
        l0, l1, l2 = lights[i, 0], lights[i, 1], lights[i, 2]
        h0, h1, h2 = half[i, 0], half[i, 1], half[i, 2]
        for q in range(L):
            cosi = max(l0 * nx[q] + l1 * ny[q] + l2 * nz[q], 0.0)
            r, g, b = col[q], col[L + q], col[2 * L + q]
            out = (q >= lanes) | (cosi < min_cosi) | (max(r, max(g, b)) >= saturated)
            nh = max(h0 * nx[q] + h1 * ny[q] + h2 * nz[q], 1e-4)
            a = 0.0 if out else cosi
            r, g, b = (0.0 if out else r), (0.0 if out else g), (0.0 if out else b)
            row[q] = a
            row[L + q] = np.inf if out else (1.0 - nh * nh) / (nh * nh)
            row[2 * L + q] = 0.0 if out else math.sqrt(cosi / cosr[q])
            row[3 * L + q], row[4 * L + q], row[5 * L + q] = r, g, b
            acc[q] += a * a
            acc[L + q] += a * r
            acc[2 * L + q] += a * g
            acc[3 * L + q] += a * b
            acc[4 * L + q] += r * r + g * g + b * b
    for q in range(lanes):
        saa, say0, say1, say2, yy = acc[q], acc[L + q], acc[2 * L + q], acc[3 * L + q], \
            acc[4 * L + q]
        inv_saa = 1.0 / max(saa, 1e-12)
        kl0, kl1, kl2 = max(say0 * inv_saa, 0.0), max(say1 * inv_saa, 0.0), \
            max(say2 * inv_saa, 0.0)
        norm = math.sqrt(kl0 * kl0 + kl1 * kl1 + kl2 * kl2)
        if norm > 1e-6:
            c0, c1, c2 = kl0 / norm, kl1 / norm, kl2 / norm
        else:
            c0 = c1 = c2 = _SQRT3
        c = (c0 + c1 + c2) * _SQRT3
        span = 1.0 - c * c
        inv_span = 1.0 / span if span > 1e-9 else 0.0
        for k, v in enumerate((saa, say0, say1, say2, yy, inv_saa, kl0, kl1, kl2, c0, c1, c2, c,
                               inv_span)):
            stats[k * L + q] = v


def ward_band_compiled(raw: npt.NDArray[np.float32], nrm: npt.NDArray[np.floating],
                       lights: npt.NDArray[np.float64], grid: npt.NDArray[np.float64],
                       limits: tuple[float, float], div: float = 1.0
                       ) -> tuple[npt.NDArray[np.float32], npt.NDArray[np.float32],
                                  npt.NDArray[np.float32]]:
    """:func:`~.ward_solve.solve_ward_band` of ``raw (N, b, W, 3)``, ``nrm (b, W, 3)``:
    (``raw`` float, or 8-/16-bit as decoded with ``div`` 255/65535, the same results)
    kd, ks ``(b, W, 3)`` and α ``(b, W)`` float32 (a gloss level's of ``limits``), with the
    constants read at call time.

    The coarse pass runs the α of :func:`~.ward_solve.coarse_steps`; where its 1/α² is twice
    the one before (to 1e-9: every step but an appended last one, on a grid that doubles), the
    lobes are squared instead of computed (and that 1/α² taken as exactly twice the other)."""
    n, b, w, _ = raw.shape
    lf = np.ascontiguousarray(lights, np.float64)
    half = lf + np.array([0.0, 0.0, 1.0])
    half /= np.maximum(np.linalg.norm(half, axis=1, keepdims=True), 1e-12)
    grid = np.ascontiguousarray(grid, np.float64)
    qf = 1.0 / (grid * grid)
    stride, coarse = ws.coarse_steps(grid)
    is_coarse = np.zeros(len(grid), np.bool_)
    is_coarse[coarse] = True
    qa = qf[coarse]
    twice = np.zeros(len(coarse), np.bool_)
    for k in range(1, len(coarse)):
        if ws.doubles(qa[k], qa[k - 1]):
            qa[k] = 2.0 * qa[k - 1]
            twice[k] = True
    # per coarse α, whether no later one is wider (its 1/α² smaller): the search may stop there
    narrowing = np.array([bool(np.all(qa[k + 1:] >= qa[k])) for k in range(len(qa))], np.bool_)
    kd = np.empty((b * w, 3), np.float32)
    ks = np.empty((b * w, 3), np.float32)
    al = np.empty(b * w, np.float32)
    _ward(compiled.kernel_samples(raw).reshape(n, b * w, 3),
          _normals(nrm).reshape(b * w, 3), lf, half,
          grid, qf, coarse, is_coarse, qa, twice, narrowing, stride, ws.MIN_COSI,
          ws.SATURATED,
          math.cos(math.radians(ws.MAX_SPECULAR_ANGLE)), ws.MIN_LOBE_SAMPLES, ws.LOBE_WIDTH,
          float(limits[0]), float(limits[1]), kd, ks, al, np.float32(div))
    return kd.reshape(b, w, 3), ks.reshape(b, w, 3), al.reshape(b, w)


def _normals(nrm: npt.NDArray[np.floating]) -> npt.NDArray[np.floating]:
    """The normals as the kernel reads them: float32 as they are (the kernel widens each to
    float64 as it reads it, the same values as a float64 copy, which took a 4 MB temporary a
    band), any other type as float64."""
    if nrm.dtype == np.float32:
        return np.ascontiguousarray(nrm)
    return np.ascontiguousarray(nrm, np.float64)
