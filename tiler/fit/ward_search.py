"""The α search of the compiled Ward fit (:mod:`.ward_kernel`), for one block of
:data:`LANES` pixels side by side in flat ``[quantity, lane]`` arrays, every loop over the lanes
branch-free so it vectorises.

A coarse pass (:func:`search`) tries the α of :func:`~.ward_solve.coarse_steps` in order, each
lobe :func:`~.exp_kernel.exp_neg` of x = tan²θh/α² or, where its 1/α² is twice the one before,
the square of that one (exp(−2x) = exp(−x)²), until no lane has enough samples in its lobe; a
fine pass (:func:`refine`) then tries, per lane, the grid's α beside its best.  At each α the
sums of every lane's samples in light order (:data:`GROUP` lights per pass, so they stay in
registers) and every lane's constrained 2×2 solve (:func:`solve`), keeping the best so far.  A
sample whose lobe value is below e⁻⁵⁰ of the peak adds 0 (as skipped: it changes no float64
sum).  The steps and constants are :func:`~.ward_solve.solve_ward_band`'s.
"""

from __future__ import annotations

import math

import numba
import numpy as np
import numpy.typing as npt

from .exp_kernel import exp_neg

_SQRT3 = 1.0 / math.sqrt(3.0)
_SKIP = 50.0  # exp(-50) ≈ 2e-22: the sample adds nothing to a float64 sum
LANES = 64  # pixels solved side by side: one vectorised loop (32: 3–13 % slower here)
GROUP = 4  # lights summed per pass over the lanes


@numba.njit(cache=True, nogil=True)
def search(samples: npt.NDArray[np.float64], stats: npt.NDArray[np.float64],
            nearest: npt.NDArray[np.float64], grid: npt.NDArray[np.float64],
            coarse: npt.NDArray[np.intp], qa: npt.NDArray[np.float64],
            inv4: npt.NDArray[np.float64], twice: npt.NDArray[np.bool_],
            narrowing: npt.NDArray[np.bool_], cos_max: float, min_lobe: int,
            lobe_width: float, sums: npt.NDArray[np.float64], lobes: npt.NDArray[np.float64],
            best: npt.NDArray[np.float64], steps: npt.NDArray[np.float64]) -> None:
    """The coarse pass for one block (the α ``grid[coarse]``, with their 1/α² ``qa``):
    ``best`` (SSE, kd, ks, α, grid index per lane) at the best of them.  ``lobes`` holds the
    step before's, squared where ``twice``: a group of lights skipped there is past
    :data:`_SKIP` here too, and skipped again.  Once every lane
    fails the lobe test, each later α would give every lane its Lambert fit again (never
    better): the search stops."""
    L = LANES
    best[:L] = np.inf
    best[L:7 * L] = 0.0
    best[7 * L:8 * L] = grid[-1]
    best[8 * L:] = 0.0
    steps[L:2 * L] = 1.0  # every lane tries every coarse α
    for j in range(coarse.shape[0]):
        _sums(samples, nearest, qa[j], inv4[j], lobe_width, sums, lobes, twice[j])
        steps[:L] = grid[coarse[j]]
        steps[2 * L:] = coarse[j]
        solve(stats, sums, steps, cos_max, min_lobe, best, False)
        if narrowing[j] and _all_fail(sums, min_lobe):
            break


@numba.njit(cache=True, nogil=True)
def refine(samples: npt.NDArray[np.float64], stats: npt.NDArray[np.float64],
            grid: npt.NDArray[np.float64], qf: npt.NDArray[np.float64],
            is_coarse: npt.NDArray[np.bool_], stride: int, cos_max: float, min_lobe: int,
            lobe_width: float, sums: npt.NDArray[np.float64], best: npt.NDArray[np.float64],
            steps: npt.NDArray[np.float64], qs: npt.NDArray[np.float64],
            centre: npt.NDArray[np.intp], way: npt.NDArray[np.intp]) -> None:
    """The fine pass, per lane (:func:`~.ward_solve.solve_ward_band`'s): the grid's α either
    side of the best coarse one (the wider first), then on along the side that gave a better
    one while each does, up to the next coarse α; each kept where better."""
    L = LANES
    for q in range(L):
        centre[q] = int(best[8 * L + q])
        way[q] = 1  # "going on": every lane tries both sides
    for r in range(-1, stride):
        if r == 0:
            continue
        any_tried = False
        for q in range(L):
            k = centre[q] + (r if r < 0 else way[q] * r)
            tried = (k >= 0) & (k < grid.shape[0]) & (r < 2 or way[q] != 0)
            k = min(max(k, 0), grid.shape[0] - 1)
            tried &= not is_coarse[k]
            any_tried |= tried
            steps[q], steps[L + q], steps[2 * L + q], qs[q] = \
                grid[k], 1.0 if tried else 0.0, k, qf[k]
        if any_tried:
            sums_at(samples, qs, lobe_width, sums)
            solve(stats, sums, steps, cos_max, min_lobe, best, False)
        for q in range(L):
            at = int(best[8 * L + q])
            if r == 1:  # the side that gave a better α, if any
                way[q] = 1 if at > centre[q] else (-1 if at < centre[q] else 0)
            elif r >= 2:  # on while each step is better
                way[q] = way[q] if at == centre[q] + way[q] * r else 0


@numba.njit(cache=True, nogil=True)
def _sums(samples: npt.NDArray[np.float64], nearest: npt.NDArray[np.float64], qa: float,
          inv4: float, lobe_width: float, sums: npt.NDArray[np.float64],
          lobe: npt.NDArray[np.float64], twice: bool) -> None:
    """Per lane at one α: Σab, Σbb, Σby (r, g, b) over the samples in light order, and the
    number of samples inside the lobe.  The lobe values go to ``lobe``: with ``twice`` (this
    α's 1/α² is twice that of the α whose lobes it holds) they are those squared, else
    :func:`~.exp_kernel.exp_neg` of x = tan²θh/α².  Branch-free over the lanes,
    so the loops vectorise (a sample with x > :data:`_SKIP` adds an exact 0, as if skipped); a
    group of lights whose smallest tan²θh over the lanes (``nearest``) puts every lane past
    :data:`_SKIP` is skipped whole (then it is past it at every later α of the pass too)."""
    sums[:] = 0.0
    L = LANES
    n = nearest.shape[0]  # a multiple of GROUP (padded with lights that add 0)
    for i in range(0, n, GROUP):
        far = True
        for j in range(GROUP):
            far &= nearest[i + j] * qa > _SKIP
        if far:
            continue
        sv = samples[i * 6 * L:(i + GROUP) * 6 * L]
        ev = lobe[i * L:(i + GROUP) * L]
        if twice:  # exp(−2x) = exp(−x)²: the lobe at this α from the one before
            for q in range(L):
                for j in range(GROUP):
                    x = sv[(6 * j + 1) * L + q] * qa
                    ev[j * L + q] = ev[j * L + q] * ev[j * L + q] if x <= _SKIP else 0.0
        else:
            for q in range(L):
                for j in range(GROUP):
                    x = sv[(6 * j + 1) * L + q] * qa
                    ev[j * L + q] = exp_neg(min(x, _SKIP)) if x <= _SKIP else 0.0
        for q in range(L):
            ab, bb, br, bg, bl, inside = sums[q], sums[L + q], sums[2 * L + q], \
                sums[3 * L + q], sums[4 * L + q], sums[5 * L + q]
            for j in range(GROUP):  # in light order: the same sums as one light at a time
                o = 6 * j * L + q
                inside += 1.0 if sv[o + L] * qa <= lobe_width else 0.0
                ab, bb, br, bg, bl = _add(sv, o, ev[j * L + q], inv4, ab, bb, br, bg, bl)
            sums[q], sums[L + q], sums[2 * L + q] = ab, bb, br
            sums[3 * L + q], sums[4 * L + q], sums[5 * L + q] = bg, bl, inside


@numba.njit(cache=True, nogil=True, inline="always")
def _add(sv: npt.NDArray[np.float64], o: int, e: float, inv4: float, ab: float, bb: float,
         br: float, bg: float, bl: float) -> tuple[float, float, float, float, float]:
    """One sample's terms (at ``sv[o + k·L]``: cosi, tan²θh, √(cosi/cosr), colour) added to a
    lane's sums Σab, Σbb, Σby (r, g, b), its Ward term ``b`` = √(cosi/cosr)·``e``·``inv4``
    (``e`` the lobe value, ``inv4`` 1/(4α²))."""
    L = LANES
    bw = sv[o + 2 * L] * e * inv4
    return (ab + sv[o] * bw, bb + bw * bw, br + bw * sv[o + 3 * L], bg + bw * sv[o + 4 * L],
            bl + bw * sv[o + 5 * L])


@numba.njit(cache=True, nogil=True)
def _all_fail(sums: npt.NDArray[np.float64], min_lobe: int) -> bool:
    """Whether no lane has ``min_lobe`` samples in the lobe.  Where no later α is wider
    (``narrowing``), a lobe holds no more samples at them, so each fails too and gives the lane
    its Lambert fit again, whose SSE does not depend on α (never better)."""
    L = LANES
    for q in range(L):
        if sums[5 * L + q] >= min_lobe:
            return False
    return True


@numba.njit(cache=True, nogil=True)
def sums_at(samples: npt.NDArray[np.float64], qs: npt.NDArray[np.float64], lobe_width: float,
             sums: npt.NDArray[np.float64]) -> None:
    """:func:`_sums` at one α per lane (1/α² in ``qs``): the fine pass, and the solve at the
    stored α."""
    sums[:] = 0.0
    L = LANES
    for i in range(0, samples.shape[0] // (6 * L), GROUP):  # lights padded to whole groups
        sv = samples[i * 6 * L:(i + GROUP) * 6 * L]
        for q in range(L):
            qa = qs[q]
            inv4 = qa * 0.25
            ab, bb, br, bg, bl, inside = sums[q], sums[L + q], sums[2 * L + q], \
                sums[3 * L + q], sums[4 * L + q], sums[5 * L + q]
            for j in range(GROUP):  # in light order
                o = 6 * j * L + q
                x = sv[o + L] * qa
                e = exp_neg(min(x, _SKIP)) if x <= _SKIP else 0.0
                inside += 1.0 if x <= lobe_width else 0.0
                ab, bb, br, bg, bl = _add(sv, o, e, inv4, ab, bb, br, bg, bl)
            sums[q], sums[L + q], sums[2 * L + q] = ab, bb, br
            sums[3 * L + q], sums[4 * L + q], sums[5 * L + q] = bg, bl, inside


@numba.njit(cache=True, nogil=True, error_model="numpy")
def solve(st: npt.NDArray[np.float64], sm: npt.NDArray[np.float64],
           steps: npt.NDArray[np.float64], cos_max: float, min_lobe: int,
           best: npt.NDArray[np.float64], again: bool) -> None:
    """Every lane's constrained solve at its α (``steps[:L]``) from its ``stats`` and
    ``sums``, kept in ``best`` with its grid index (``steps[2L:3L]``) where the lane tries it
    (``steps[L:2L]`` ≠ 0) and its SSE is the smallest so far (``again``: where the best has
    ks > 0, and the α left as it is):
    :func:`~.ward_solve.solve_ward_band`'s steps, as selects (so the lane loop vectorises; the
    unused side of a select stays finite)."""
    L = LANES
    cos2, obtuse = cos_max * cos_max, cos_max < 0.0
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
        c, inv_span = st[12 * L + q], st[13 * L + q]
        xg = (k0 + k1 + k2) * _SQRT3
        xc = k0 * c0 + k1 * c1 + k2 * c2
        wide = inv_span > 0.0
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
        # within cos_max of the cone: dot ≥ cos_max·|f|·|p|, squared (no square roots)
        dot = f0 * p0 + f1 * p1 + f2 * p2
        nc2 = p0 * p0 + p1 * p1 + p2 * p2
        far = cos2 * (f0 * f0 + f1 * f1 + f2 * f2) * nc2
        near = (nc2 > 0.0) & (((dot >= 0.0) & (dot * dot >= far))
                              | (obtuse & ((dot >= 0.0) | (dot * dot <= far))))
        s0 = min(f0 if near else p0, 1.0) if ok else 0.0
        s1 = min(f1 if near else p1, 1.0) if ok else 0.0
        s2 = min(f2 if near else p2, 1.0) if ok else 0.0
        # kd refitted for ks; a channel whose kd would be negative: kd = 0, its ks alone
        inv_sbb = 1.0 / max(sbb, 1e-30)
        r0, r1, r2 = (say0 - sab * s0) * inv_saa, (say1 - sab * s1) * inv_saa, \
            (say2 - sab * s2) * inv_saa
        s0 = min(max(sby0 * inv_sbb, 0.0), 1.0) if ok and r0 < 0.0 else s0
        s1 = min(max(sby1 * inv_sbb, 0.0), 1.0) if ok and r1 < 0.0 else s1
        s2 = min(max(sby2 * inv_sbb, 0.0), 1.0) if ok and r2 < 0.0 else s2
        d0 = (0.0 if r0 < 0.0 else r0) if ok else st[6 * L + q]
        d1 = (0.0 if r1 < 0.0 else r1) if ok else st[7 * L + q]
        d2 = (0.0 if r2 < 0.0 else r2) if ok else st[8 * L + q]
        sse = (yy - 2 * (d0 * say0 + s0 * sby0 + d1 * say1 + s1 * sby1 + d2 * say2 + s2 * sby2)
               + (d0 * d0 + d1 * d1 + d2 * d2) * saa + 2 * (d0 * s0 + d1 * s1 + d2 * s2) * sab
               + (s0 * s0 + s1 * s1 + s2 * s2) * sbb)
        # a select, not a branch on ``again``: a branch in the loop kept it from vectorising
        kept = (best[4 * L + q] > 0.0) | (best[5 * L + q] > 0.0) | (best[6 * L + q] > 0.0)
        better = (again & kept) | (not again and steps[L + q] != 0.0 and sse < best[q])
        best[7 * L + q] = steps[q] if better and not again else best[7 * L + q]
        best[8 * L + q] = steps[2 * L + q] if better and not again else best[8 * L + q]
        best[q] = sse if better else best[q]
        best[L + q] = d0 if better else best[L + q]
        best[2 * L + q] = d1 if better else best[2 * L + q]
        best[3 * L + q] = d2 if better else best[3 * L + q]
        best[4 * L + q] = s0 if better else best[4 * L + q]
        best[5 * L + q] = s1 if better else best[5 * L + q]
        best[6 * L + q] = s2 if better else best[6 * L + q]
