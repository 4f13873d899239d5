"""The α-grid solve of :mod:`.ward_solve`, compiled (Numba).

numpy evaluates the Ward term of every sample of every pixel at every α of the grid as whole
``(N, b, W)`` arrays (≈ 10 passes over memory per α).  Compiled, the pixels are solved
:data:`_LANES` side by side, one parallel task per group, in flat ``[quantity, lane]`` arrays
with a fixed lane count, so every loop over the lanes is branch-free and vectorises: each pixel's
samples are gathered once (cosi, tan²θh, √(cosi/cosr), colour; an excluded sample, a padding lane
or light, kept as one that adds exactly 0); then per α the lobe of every sample
(:func:`~.exp_kernel.exp_neg` instead of libm's ``exp``, or, where the grid's 1/α² is twice
the one three steps before, the square of that lobe: exp(−2x) = exp(−x)²), the sums of each
pixel's samples in light order (:data:`_GROUP` lights per pass, so the sums stay in
registers), and every pixel's constrained 2×2 solve, keeping the best α so far; once no pixel
of a group has enough samples in its lobe, the narrower α are not tried (each would give the
same Lambert fit again, never better: the results are those of the whole grid).  A sample whose
lobe value is below e⁻⁵⁰ of the peak adds 0 (as skipped: it changes no float64 sum).  The steps
and constants are :func:`~lanterna.tiler.fit.ward_solve.solve_ward_band`'s (the reference,
checked in tests/python/fit/test_engine_kernels.py); sums run in another order, so a pixel
whose best α is a near tie may pick the neighbouring grid value.
"""

from __future__ import annotations

import math

import numba
import numpy as np
import numpy.typing as npt

from . import compiled
from . import ward_solve as ws
from .compiled import unit
from .exp_kernel import exp_neg

_SQRT3 = 1.0 / math.sqrt(3.0)
_SKIP = 50.0  # exp(-50) ≈ 2e-22: the sample adds nothing to a float64 sum
_LANES = 32  # pixels solved side by side: one parallel task, one vectorised loop
_CHAIN = 3  # a lobe is the square of the one this many α before, where the grid allows
_GROUP = 4  # lights summed per pass over the lanes
_CHUNK = 64  # blocks per parallel task (their scratch allocated once)
_STATS = 12  # Σaa, Σay (r, g, b), Σyy, 1/Σaa, Lambert-only kd (r, g, b), its chroma


@numba.njit(cache=True, parallel=True, nogil=True)
def _ward(raw: npt.NDArray[np.generic], nrm: npt.NDArray[np.float64],
          lights: npt.NDArray[np.float64], half: npt.NDArray[np.float64],
          grid: npt.NDArray[np.float64], qa: npt.NDArray[np.float64],
          twice: npt.NDArray[np.bool_], narrowing: npt.NDArray[np.bool_], min_cosi: float,
          saturated: float, cos_max: float,
          min_lobe: int, lobe_width: float, lo: float, hi: float,
          kd_out: npt.NDArray[np.float32],
          ks_out: npt.NDArray[np.float32], al_out: npt.NDArray[np.float32], d: np.float32
          ) -> None:
    n, p = raw.shape[0], raw.shape[1]
    ng = -(-n // _GROUP) * _GROUP  # lights padded to whole groups
    inv4 = qa * 0.25
    blocks = (p + _LANES - 1) // _LANES
    for chunk in numba.prange((blocks + _CHUNK - 1) // _CHUNK):
        # a chunk's scratch, allocated once: for each block every part is written before it
        # is read (zeroing it per block was a memset of 54 KB per 32 pixels)
        samples = np.zeros(ng * 6 * _LANES)  # [light, quantity, lane], padded ones add 0
        stats = np.zeros(_STATS * _LANES)
        sums = np.empty(6 * _LANES)
        best = np.empty(8 * _LANES)  # SSE, kd (r, g, b), ks (r, g, b), α of the best α so far
        nearest = np.empty(ng)  # per light, the smallest tan²θh of the lanes
        lobes = np.zeros(_CHAIN * ng * _LANES)
        qs = np.empty(_LANES)
        for block in range(chunk * _CHUNK, min(blocks, (chunk + 1) * _CHUNK)):
            q0 = block * _LANES
            lanes = min(p, q0 + _LANES) - q0
            _samples(raw, q0, lanes, nrm, lights, half, min_cosi, saturated, samples, stats, d)
            for i in range(ng):
                row = samples[(i * 6 + 1) * _LANES:(i * 6 + 2) * _LANES]
                if i >= n:  # a padding light (_samples wrote the lights, padding lanes excluded)
                    row[:] = np.inf
                nearest[i] = row.min()
            _search(samples, stats, nearest, grid, qa, inv4, twice, narrowing, cos_max,
                    min_lobe, lobe_width, sums, lobes, best)
            # the best α as its gloss level's, and kd, ks solved again there where ks > 0
            for q in range(_LANES):
                level = min(max(np.rint((best[7 * _LANES + q] - lo) / (hi - lo) * 255.0), 0.0),
                            255.0)
                alpha = lo + level / 255.0 * (hi - lo)
                best[7 * _LANES + q] = alpha
                qs[q] = 1.0 / (alpha * alpha)
            _sums_at(samples, qs, sums)
            _solve(stats, sums, 0.0, cos_max, 0, best, True)
            for q in range(lanes):
                for c in range(3):
                    kd_out[q0 + q, c] = best[(1 + c) * _LANES + q]
                    ks_out[q0 + q, c] = best[(4 + c) * _LANES + q]
                al_out[q0 + q] = best[7 * _LANES + q]


@numba.njit(cache=True, nogil=True)
def _search(samples: npt.NDArray[np.float64], stats: npt.NDArray[np.float64],
            nearest: npt.NDArray[np.float64], grid: npt.NDArray[np.float64],
            qa: npt.NDArray[np.float64], inv4: npt.NDArray[np.float64],
            twice: npt.NDArray[np.bool_], narrowing: npt.NDArray[np.bool_], cos_max: float,
            min_lobe: int, lobe_width: float, sums: npt.NDArray[np.float64],
            lobes: npt.NDArray[np.float64], best: npt.NDArray[np.float64]) -> None:
    """The α grid for one block: ``best`` (SSE, kd, ks, α per lane) at the best α.  A lobe
    slot is read (``twice``) only for a group of lights computed three α before in this block:
    a group skipped there is past :data:`_SKIP` here too, and skipped again."""
    best[:_LANES] = np.inf
    best[_LANES:7 * _LANES] = 0.0
    best[7 * _LANES:] = grid[-1]
    for k in range(grid.shape[0]):
        _sums(samples, nearest, qa[k], inv4[k], lobe_width, sums, lobes, k % _CHAIN, twice[k])
        _solve(stats, sums, grid[k], cos_max, min_lobe, best, False)
        if narrowing[k] and _all_fail(sums, min_lobe):
            break  # every lane failed the lobe test: each later α is its Lambert again


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _samples(raw: npt.NDArray[np.generic], q0: int, lanes: int, nrm: npt.NDArray[np.float64],
             lights: npt.NDArray[np.float64], half: npt.NDArray[np.float64], min_cosi: float,
             saturated: float, samples: npt.NDArray[np.float64],
             stats: npt.NDArray[np.float64], d: np.float32) -> None:
    """Pixels ``q0 …`` as the ``lanes`` first lanes of ``samples``: cosi, tan²θh, √(cosi/cosr)
    and colour per light, an excluded sample (a padding lane's too) as one that adds nothing
    (tan²θh = ∞, the rest 0); and their ``stats``: Σaa, Σay (r, g, b), Σyy, 1/Σaa, the
    Lambert-only kd and its chroma.  Light by light, branch-free over the lanes (so the loop,
    its square root and division included, vectorises); each lane's sums in light order, an
    excluded sample adding an exact 0."""
    L = _LANES
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
        for c, v in enumerate((saa, say0, say1, say2, yy, inv_saa, kl0, kl1, kl2, c0, c1, c2)):
            stats[c * L + q] = v


@numba.njit(cache=True, nogil=True)
def _sums(samples: npt.NDArray[np.float64], nearest: npt.NDArray[np.float64], qa: float,
          inv4: float, lobe_width: float, sums: npt.NDArray[np.float64],
          lobe: npt.NDArray[np.float64], s: int, twice: bool) -> None:
    """Per lane at one α: Σab, Σbb, Σby (r, g, b) over the samples in light order, and the
    number of samples inside the lobe.  The lobe values go to slot ``s`` of ``lobe``: with
    ``twice`` (this α's 1/α² is twice that of the α whose lobes the slot holds) they are those
    squared, else :func:`~.exp_kernel.exp_neg` of x = tan²θh/α².  Branch-free over the lanes,
    so the loops vectorise (a sample with x > :data:`_SKIP` adds an exact 0, as if skipped); a
    group of lights whose smallest tan²θh over the lanes (``nearest``) puts every lane past
    :data:`_SKIP` is skipped whole (then it is past it at every later α of its chain too)."""
    sums[:] = 0.0
    L = _LANES
    n = nearest.shape[0]  # a multiple of _GROUP (padded with lights that add 0)
    for i in range(0, n, _GROUP):
        far = True
        for j in range(_GROUP):
            far &= nearest[i + j] * qa > _SKIP
        if far:
            continue
        sv = samples[i * 6 * L:(i + _GROUP) * 6 * L]
        ev = lobe[(s * n + i) * L:(s * n + i + _GROUP) * L]
        if twice:  # exp(−2x) = exp(−x)²: the lobe at this α from the one 3 α before
            for q in range(L):
                for j in range(_GROUP):
                    x = sv[(6 * j + 1) * L + q] * qa
                    ev[j * L + q] = ev[j * L + q] * ev[j * L + q] if x <= _SKIP else 0.0
        else:
            for q in range(L):
                for j in range(_GROUP):
                    x = sv[(6 * j + 1) * L + q] * qa
                    ev[j * L + q] = exp_neg(min(x, _SKIP)) if x <= _SKIP else 0.0
        for q in range(L):
            ab, bb, br, bg, bl, inside = sums[q], sums[L + q], sums[2 * L + q], \
                sums[3 * L + q], sums[4 * L + q], sums[5 * L + q]
            for j in range(_GROUP):  # in light order: the same sums as one light at a time
                o = 6 * j * L + q
                inside += 1.0 if sv[o + L] * qa <= lobe_width else 0.0
                bw = sv[o + 2 * L] * ev[j * L + q] * inv4
                ab += sv[o] * bw
                bb += bw * bw
                br += bw * sv[o + 3 * L]
                bg += bw * sv[o + 4 * L]
                bl += bw * sv[o + 5 * L]
            sums[q], sums[L + q], sums[2 * L + q] = ab, bb, br
            sums[3 * L + q], sums[4 * L + q], sums[5 * L + q] = bg, bl, inside


@numba.njit(cache=True, nogil=True)
def _all_fail(sums: npt.NDArray[np.float64], min_lobe: int) -> bool:
    """Whether no lane has ``min_lobe`` samples in the lobe.  Where no later α is wider
    (``narrowing``), a lobe holds no more samples at them, so each fails too and gives the lane
    its Lambert fit again, whose SSE does not depend on α (never better)."""
    L = _LANES
    for q in range(L):
        if sums[5 * L + q] >= min_lobe:
            return False
    return True


@numba.njit(cache=True, nogil=True)
def _sums_at(samples: npt.NDArray[np.float64], qs: npt.NDArray[np.float64],
             sums: npt.NDArray[np.float64]) -> None:
    """:func:`_sums` at one α per lane (1/α² in ``qs``), for the solve at the stored α."""
    sums[:] = 0.0
    L = _LANES
    for i in range(samples.shape[0] // (6 * L)):
        sv = samples[i * 6 * L:(i + 1) * 6 * L]
        for q in range(L):
            x = sv[L + q] * qs[q]
            e = exp_neg(min(x, _SKIP)) if x <= _SKIP else 0.0
            bw = sv[2 * L + q] * e * (qs[q] * 0.25)
            sums[q] += sv[q] * bw
            sums[L + q] += bw * bw
            sums[2 * L + q] += bw * sv[3 * L + q]
            sums[3 * L + q] += bw * sv[4 * L + q]
            sums[4 * L + q] += bw * sv[5 * L + q]


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _solve(st: npt.NDArray[np.float64], sm: npt.NDArray[np.float64], alpha: float,
           cos_max: float, min_lobe: int, best: npt.NDArray[np.float64], again: bool) -> None:
    """Every lane's constrained solve at ``alpha`` from its ``stats`` and ``sums``, kept in
    ``best`` where its SSE is the smallest so far (``again``: where the best has ks > 0, and
    ``alpha`` left as it is): :func:`~.ward_solve.solve_ward_band`'s steps, as selects (so the
    lane loop vectorises; the unused side of a select stays finite)."""
    L = _LANES
    for q in range(L):
        saa, say0, say1, say2 = st[q], st[L + q], st[2 * L + q], st[3 * L + q]
        yy, inv_saa = st[4 * L + q], st[5 * L + q]
        sab, sbb, sby0, sby1, sby2 = sm[q], sm[L + q], sm[2 * L + q], sm[3 * L + q], sm[4 * L + q]
        det = saa * sbb - sab * sab
        ok = (det > 1e-12 * max(saa * sbb, 1e-30)) & (sm[5 * L + q] >= min_lobe)
        inv = 1.0 / det if ok else 0.0
        k0 = (saa * sby0 - sab * say0) * inv
        k1 = (saa * sby1 - sab * say1) * inv
        k2 = (saa * sby2 - sab * say2) * inv
        # the ks colour kept within cos_max of the grey–diffuse cone, else projected onto it
        c0, c1, c2 = st[9 * L + q], st[10 * L + q], st[11 * L + q]
        c = (c0 + c1 + c2) * _SQRT3
        xg = (k0 + k1 + k2) * _SQRT3
        xc = k0 * c0 + k1 * c1 + k2 * c2
        span = 1.0 - c * c
        wide = span > 1e-9
        inv_span = 1.0 / span if wide else 0.0
        u = (xg - c * xc) * inv_span
        v = (xc - c * xg) * inv_span
        inside = wide & (u >= 0.0) & (v >= 0.0)
        pg = max(xg, 0.0)
        pc = max(xc, 0.0) if wide else 0.0
        chroma = pc > pg
        u = u if inside else (0.0 if chroma else pg)
        v = v if inside else (pc if chroma else 0.0)
        p0, p1, p2 = u * _SQRT3 + v * c0, u * _SQRT3 + v * c1, u * _SQRT3 + v * c2
        f0, f1, f2 = max(k0, 0.0), max(k1, 0.0), max(k2, 0.0)
        dot = f0 * p0 + f1 * p1 + f2 * p2
        nc = math.sqrt(p0 * p0 + p1 * p1 + p2 * p2)
        near = (nc > 0.0) & (dot >= cos_max * math.sqrt(f0 * f0 + f1 * f1 + f2 * f2) * nc)
        s0 = min(f0 if near else p0, 1.0) if ok else 0.0
        s1 = min(f1 if near else p1, 1.0) if ok else 0.0
        s2 = min(f2 if near else p2, 1.0) if ok else 0.0
        # kd refitted for ks; a channel whose kd would be negative: kd = 0, its ks alone
        sbb_safe = max(sbb, 1e-30)
        r0, r1, r2 = (say0 - sab * s0) * inv_saa, (say1 - sab * s1) * inv_saa, \
            (say2 - sab * s2) * inv_saa
        s0 = min(max(sby0 / sbb_safe, 0.0), 1.0) if ok and r0 < 0.0 else s0
        s1 = min(max(sby1 / sbb_safe, 0.0), 1.0) if ok and r1 < 0.0 else s1
        s2 = min(max(sby2 / sbb_safe, 0.0), 1.0) if ok and r2 < 0.0 else s2
        d0 = (0.0 if r0 < 0.0 else r0) if ok else st[6 * L + q]
        d1 = (0.0 if r1 < 0.0 else r1) if ok else st[7 * L + q]
        d2 = (0.0 if r2 < 0.0 else r2) if ok else st[8 * L + q]
        sse = (yy - 2 * (d0 * say0 + s0 * sby0 + d1 * say1 + s1 * sby1 + d2 * say2 + s2 * sby2)
               + (d0 * d0 + d1 * d1 + d2 * d2) * saa + 2 * (d0 * s0 + d1 * s1 + d2 * s2) * sab
               + (s0 * s0 + s1 * s1 + s2 * s2) * sbb)
        # a select, not a branch on ``again``: a branch in the loop kept it from vectorising
        kept = (best[4 * L + q] > 0.0) | (best[5 * L + q] > 0.0) | (best[6 * L + q] > 0.0)
        better = (again & kept) | (not again and sse < best[q])
        best[7 * L + q] = alpha if better and not again else best[7 * L + q]
        best[q] = sse if better else best[q]
        best[L + q] = d0 if better else best[L + q]
        best[2 * L + q] = d1 if better else best[2 * L + q]
        best[3 * L + q] = d2 if better else best[3 * L + q]
        best[4 * L + q] = s0 if better else best[4 * L + q]
        best[5 * L + q] = s1 if better else best[5 * L + q]
        best[6 * L + q] = s2 if better else best[6 * L + q]


def ward_band_compiled(raw: npt.NDArray[np.float32], nrm: npt.NDArray[np.floating],
                       lights: npt.NDArray[np.float64], grid: npt.NDArray[np.float64],
                       limits: tuple[float, float], div: float = 1.0
                       ) -> tuple[npt.NDArray[np.float32], npt.NDArray[np.float32],
                                  npt.NDArray[np.float32]]:
    """:func:`~.ward_solve.solve_ward_band` of ``raw (N, b, W, 3)``, ``nrm (b, W, 3)``:
    (``raw`` float, or 8-/16-bit as decoded with ``div`` 255/65535, the same results)
    kd, ks ``(b, W, 3)`` and α ``(b, W)`` float32 (a gloss level's of ``limits``), with the
    constants read at call time.

    Where the grid's 1/α² is twice the one :data:`_CHAIN` steps before (to 1e-9), the lobes are
    squared instead of computed (and that 1/α² taken as exactly twice the other)."""
    n, b, w, _ = raw.shape
    lf = np.ascontiguousarray(lights, np.float64)
    half = lf + np.array([0.0, 0.0, 1.0])
    half /= np.maximum(np.linalg.norm(half, axis=1, keepdims=True), 1e-12)
    grid = np.asarray(grid, np.float64)
    qa = 1.0 / (grid * grid)
    twice = np.zeros(len(grid), np.bool_)
    for k in range(_CHAIN, len(grid)):
        if abs(qa[k] - 2.0 * qa[k - _CHAIN]) <= 1e-9 * qa[k]:
            qa[k] = 2.0 * qa[k - _CHAIN]
            twice[k] = True
    # per α, whether no later α is wider (its 1/α² smaller): the search may stop there
    narrowing = np.array([bool(np.all(qa[k + 1:] >= qa[k])) for k in range(len(qa))], np.bool_)
    kd = np.empty((b * w, 3), np.float32)
    ks = np.empty((b * w, 3), np.float32)
    al = np.empty(b * w, np.float32)
    _ward(compiled.kernel_samples(raw).reshape(n, b * w, 3),
          np.ascontiguousarray(nrm, np.float64).reshape(b * w, 3), lf, half,
          np.ascontiguousarray(grid, np.float64), qa, twice, narrowing, ws.MIN_COSI, ws.SATURATED,
          math.cos(math.radians(ws.MAX_SPECULAR_ANGLE)), ws.MIN_LOBE_SAMPLES, ws.LOBE_WIDTH,
          float(limits[0]), float(limits[1]), kd, ks, al, np.float32(div))
    return kd.reshape(b, w, 3), ks.reshape(b, w, 3), al.reshape(b, w)
