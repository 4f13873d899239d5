"""The per-band α-grid solve of the Lambert + Ward fit, in numpy: the reference kernel.

:func:`solve_ward_band` is what :func:`~lanterna.tiler.fit.ward.fit_ward` runs on each band of
rows; :mod:`.ward_kernel` compiles the same steps per pixel (Numba) and is checked against it.

Per pixel and α, the three channels share one 2×2 Gram matrix ``[[Σaa, Σab], [Σab, Σbb]]``
(``a = cosi``, ``b`` the Ward term), so after profiling kd out the SSE is
``D·Σ_c (ks_c − k̂_c)² + const`` with the same ``D = det/Σaa`` for every channel: the best ks
under any constraint on its colour is the Euclidean projection of the unconstrained
``k̂ = (k̂_r, k̂_g, k̂_b)`` onto the allowed set, and ``kd_c = (Σa·y_c − Σab·ks_c)/Σaa``.
The allowed set is the cone between grey and the pixel's Lambert-only diffuse colour
(``ks = u·grey + v·chroma(kd)``, ``u, v ≥ 0``: a dielectric's white highlight, a metal's
tinted one, or a mix) widened by :data:`MAX_SPECULAR_ANGLE`: a per-channel fit within that
angle of the cone is kept, one further off is projected onto it.  This removes the saturated
green highlights the free per-channel fit puts along silhouettes (docs/fitting.md).  A channel
whose kd would then be negative keeps kd = 0 and its own ks (as before the constraint).  An α
whose lobe holds fewer than :data:`MIN_LOBE_SAMPLES` valid samples is not significant there
(the isolated white sparkles under top light).
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

F64 = npt.NDArray[np.float64]

#: Samples with ``n·l`` below this are shadowed/grazing and excluded.
MIN_COSI = 0.05
#: Samples with any channel at or above this (stack units, 0–1) are saturated and excluded.
SATURATED = 0.99
#: Largest angle (degrees) between a fitted ks colour and the cone from grey to the pixel's
#: diffuse colour; a fit further off is projected onto the cone (180: unconstrained).
MAX_SPECULAR_ANGLE = 20.0
#: An α is tried only where at least this many valid samples lie inside its lobe
#: (``tan²θh ≤ LOBE_WIDTH·α²``, the lobe above e^−1.5 ≈ 22 % of its peak): a lobe fitted to one
#: or two samples is a sparkle, not a material (the pixel stays Lambert at that α).
MIN_LOBE_SAMPLES = 3
LOBE_WIDTH = 1.5

_GREY = np.full(3, 1.0 / np.sqrt(3.0))


def project_specular(ks: F64, chroma: F64) -> F64:
    """Project ks colours ``(…, 3)`` onto the cone ``{u·grey + v·chroma : u, v ≥ 0}``.

    ``chroma`` ``(…, 3)`` unit vectors with non-negative components (the diffuse colour's
    direction).  Where chroma is grey (the cone is a ray), onto the grey ray.
    """
    c = chroma @ _GREY
    xg = ks @ _GREY
    xc = np.einsum("...k,...k->...", ks, chroma)
    span = 1.0 - c * c
    wide = span > 1e-9
    inv = np.where(wide, 1.0 / np.where(wide, span, 1.0), 0.0)
    u = (xg - c * xc) * inv
    v = (xc - c * xg) * inv
    inside = wide & (u >= 0) & (v >= 0)
    # outside: the nearer of the two rays (the one with the larger positive projection)
    pg, pc = np.maximum(xg, 0.0), np.where(wide, np.maximum(xc, 0.0), 0.0)
    on_chroma = pc > pg
    u = np.where(inside, u, np.where(on_chroma, 0.0, pg))
    v = np.where(inside, v, np.where(on_chroma, pc, 0.0))
    out: F64 = u[..., None] * _GREY + v[..., None] * chroma
    return out


def constrain_specular(ks: F64, chroma: F64, max_angle: float) -> F64:
    """``max(ks, 0)`` where it lies within ``max_angle`` degrees of the cone
    (:func:`project_specular`), else its projection onto the cone."""
    free = np.maximum(ks, 0.0)
    cone = project_specular(ks, chroma)
    dot = np.einsum("...k,...k->...", free, cone)
    nf = np.sqrt(np.einsum("...k,...k->...", free, free))
    nc = np.sqrt(np.einsum("...k,...k->...", cone, cone))
    near = (dot >= np.cos(np.radians(max_angle)) * nf * nc) & (nc > 0)
    out: F64 = np.where(near[..., None], free, cone)
    return out


def diffuse_chroma(kd: F64) -> F64:
    """The unit direction of each diffuse colour ``(…, 3)`` (grey where it is about black)."""
    norm = np.sqrt(np.einsum("...k,...k->...", kd, kd))[..., None]
    out: F64 = np.where(norm > 1e-6, kd / np.maximum(norm, 1e-6), _GREY)
    return out


def ward_terms(nrm: F64, lights: F64) -> tuple[F64, F64, F64]:
    """Per sample ``(N, …)``: ``cosi = max(0, n·l)``, ``tan²θh`` and ``√(cosi/cosr)``."""
    half = lights + np.array([0.0, 0.0, 1.0])
    half /= np.maximum(np.linalg.norm(half, axis=1, keepdims=True), 1e-12)
    cosi = np.maximum(np.einsum("nc,...c->n...", lights, nrm), 0.0)
    cosr = np.maximum(nrm[..., 2], 1e-4)
    nh = np.maximum(np.einsum("nc,...c->n...", half, nrm), 1e-4)
    tan2 = (1.0 - nh * nh) / (nh * nh)
    return cosi, tan2, np.sqrt(cosi / cosr)


def snap_alpha(alpha: F64, limits: tuple[float, float]) -> F64:
    """The α of the 8-bit gloss level nearest ``alpha`` (``α = lo + level/255·(hi − lo)``, the
    layer's ``glossLimits``; outside them, the nearer end)."""
    lo, hi = limits
    level = np.clip(np.round((np.asarray(alpha, np.float64) - lo) / (hi - lo) * 255.0), 0, 255)
    out: F64 = lo + level / 255.0 * (hi - lo)
    return out


def doubles(q: float, before: float) -> bool:
    """Whether the 1/α² ``q`` is twice ``before`` (to 1e-9): then its lobes are those of
    ``before`` squared (exp(−2x) = exp(−x)²)."""
    return abs(q - 2.0 * before) <= 1e-9 * q


def doubling_stride(grid: F64) -> int:
    """The steps after which the grid's first 1/α² doubles (:func:`doubles`): the default
    grid's 2, the stride of its coarse pass; 1 where none does (every α is then tried in one
    pass)."""
    qa = 1.0 / (np.asarray(grid, np.float64) ** 2)
    for c in range(1, len(qa)):
        if doubles(qa[c], qa[0]):
            return c
    return 1


def coarse_steps(grid: F64) -> tuple[int, npt.NDArray[np.intp]]:
    """The search's coarse pass: every :func:`doubling_stride`-th index of ``grid`` from the
    first, and the last; with the stride."""
    stride = doubling_stride(grid)
    idx = np.arange(0, len(grid), stride)
    if idx[-1] != len(grid) - 1:
        idx = np.append(idx, len(grid) - 1)
    return stride, idx.astype(np.intp)


def solve_ward_band(raw: F64, nrm: F64, lights: F64, grid: F64,
                    limits: tuple[float, float]) -> tuple[F64, F64, F64]:
    """Fit one band: ``raw (N, b, W, 3)``, ``nrm (b, W, 3)`` → kd, ks ``(b, W, 3)``, α ``(b, W)``.

    The search is coarse to fine: the α of :func:`coarse_steps` are tried in order (the first of
    equal SSEs is kept); then, per pixel, the grid's α either side of its best (the wider
    first), each kept where its SSE is smaller still, and on along the side that gave a better
    one while each does, up to the next coarse α.  Where a pixel's SSE over the grid falls then
    rises (one minimum, even a lopsided one, or a fall cut short by the lobe test), that is the
    α the whole grid gives.  The
    best is then stored as its gloss level's α (:func:`snap_alpha`), and kd, ks of a pixel with
    a specular term are solved again at that α (a lobe test no longer applies), so the maps fit
    the α the layer stores.  See :func:`~lanterna.tiler.fit.ward.fit_ward` for the model and
    the module docstring for the constraint.
    """
    b, w = nrm.shape[:2]
    cosi, tan2, root = ward_terms(nrm, lights)
    valid = (cosi >= MIN_COSI) & (raw.max(axis=3) < SATURATED)  # (N, b, W)
    y = raw * valid[..., None]
    yy = np.einsum("nbwc,nbwc->bwc", y, y)
    a = cosi * valid
    g = root * valid
    saa = np.einsum("nbw,nbw->bw", a, a)
    say = np.einsum("nbw,nbwc->bwc", a, y)
    kd_l = np.maximum(say / np.maximum(saa, 1e-12)[..., None], 0.0)
    chroma = diffuse_chroma(kd_l)

    def solve(a2: F64 | float, lobe_test: bool) -> tuple[F64, F64, F64]:
        """kd, ks and the SSE of every pixel at α² ``a2`` (a scalar, or one per pixel)."""
        bw = g * np.exp(-tan2 / a2) / (4.0 * a2)
        sab = np.einsum("nbw,nbw->bw", a, bw)
        sbb = np.einsum("nbw,nbw->bw", bw, bw)
        sby = np.einsum("nbw,nbwc->bwc", bw, y)
        det = saa * sbb - sab * sab
        ok = det > 1e-12 * np.maximum(saa * sbb, 1e-30)
        if lobe_test:
            ok &= np.count_nonzero(valid & (tan2 <= a2 * LOBE_WIDTH), axis=0) >= MIN_LOBE_SAMPLES
        inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)[..., None]
        ks = (saa[..., None] * sby - sab[..., None] * say) * inv
        ks = constrain_specular(ks, chroma, MAX_SPECULAR_ANGLE)
        ks = np.where(ok[..., None], np.minimum(ks, 1.0), 0.0)  # stored 0–1
        kd_raw = (say - sab[..., None] * ks) / np.maximum(saa, 1e-12)[..., None]
        kd = np.where(ok[..., None], np.maximum(kd_raw, 0.0), kd_l)
        # a channel whose kd would be negative: kd = 0 and its ks alone (capped)
        only = np.minimum(np.maximum(sby / np.maximum(sbb, 1e-30)[..., None], 0.0), 1.0)
        ks = np.where(ok[..., None] & (kd_raw < 0), only, ks)
        return kd, ks, _sse(yy, say, saa, kd, ks, sab, sby, sbb)

    best = np.full((b, w), np.inf)
    kd_b = np.zeros((b, w, 3))
    ks_b = np.zeros((b, w, 3))
    al_b = np.full((b, w), grid[-1])

    def keep(a2: F64 | float, alpha: F64 | float,
             tried: npt.NDArray[np.bool_] | bool) -> npt.NDArray[np.bool_]:
        """Solve at α (one, or one per pixel); keep it where tried and better."""
        nonlocal best, kd_b, ks_b, al_b
        kd, ks, sse = solve(a2, True)
        better: npt.NDArray[np.bool_] = tried & (sse < best)
        best = np.where(better, sse, best)
        kd_b = np.where(better[..., None], kd, kd_b)
        ks_b = np.where(better[..., None], ks, ks_b)
        al_b = np.where(better, alpha, al_b)
        return better

    stride, coarse = coarse_steps(grid)
    at = np.zeros((b, w), np.intp)  # the grid index of the best α so far
    for k in coarse:
        at = np.where(keep(grid[k] * grid[k], grid[k], True), k, at)
    # the fine pass: the α either side of the best coarse one, then on along the side that
    # gave a better one while each does (up to the next coarse α)
    tried_coarse = np.zeros(len(grid), np.bool_)
    tried_coarse[coarse] = True
    centre = at

    def step(k: npt.NDArray[np.intp], tried: npt.NDArray[np.bool_]) -> npt.NDArray[np.bool_]:
        nonlocal at
        inside = (k >= 0) & (k < len(grid))
        kk = np.clip(k, 0, len(grid) - 1)
        tried = tried & inside & ~tried_coarse[kk]
        alpha = grid[kk]
        better = keep(alpha * alpha, alpha, tried)
        at = np.where(better, kk, at)
        return better

    step(centre - 1, np.ones((b, w), np.bool_))
    step(centre + 1, np.ones((b, w), np.bool_))
    way = np.sign(at - centre)
    going = way != 0
    for r in range(2, stride):
        going = step(centre + way * r, going)
    al_s = snap_alpha(al_b, limits)
    kd, ks, _ = solve(al_s * al_s, False)
    again = (ks_b.max(axis=-1) > 0)[..., None]
    return np.where(again, kd, kd_b), np.where(again, ks, ks_b), al_s


def _sse(yy: F64, say: F64, saa: F64, kd: F64, ks: F64, sab: F64, sby: F64, sbb: F64) -> F64:
    """``Σ_c Σ_n (y − kd·a − ks·b)²`` from the sums (summed over the channels)."""
    out: F64 = (yy - 2 * (kd * say + ks * sby) + kd * kd * saa[..., None]
                + 2 * kd * ks * sab[..., None] + ks * ks * sbb[..., None]).sum(axis=-1)
    return out
