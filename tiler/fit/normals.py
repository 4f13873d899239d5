"""Robust photometric stereo on a band of pixels: rank-window selection, then IRLS.

The caller reads the images (whole or in row bands) and passes the samples of ``P`` pixels.
Each pixel is solved independently and deterministically (no BLAS reductions, whose bits can
depend on the batch size), so banding cannot change a single bit.  See ``docs/fitting.md``.
"""

from __future__ import annotations

from typing import Literal

import numpy as np
import numpy.typing as npt

from .luminance_kernel import luminance_compiled
from .normals_kernel import rank_window_normals

F64 = npt.NDArray[np.float64]
F32 = npt.NDArray[np.float32]
Estimator = Literal["tukey", "huber"]

#: Per-pixel rank window of the initial selection (fractions of the light count).
RANK_WINDOW = (0.25, 0.9)
#: Samples darker than this fraction of the pixel's brightest sample count as shadowed.
SHADOW_FRACTION = 0.05
#: Maximum number of reweighting steps after the initial (0/1-weighted) solve.
ITERATIONS = 10
#: Default tuning constants (95 % efficiency under Gaussian noise), in robust-sigma units.
TUNING: dict[str, float] = {"tukey": 4.685, "huber": 1.345}
#: Turns the median absolute residual into a Gaussian-consistent scale.
MAD_TO_SIGMA = 1.4826

_CHUNK = 256  # pixels solved at once: the (chunk, N) float64 temporaries stay in cache
_RIDGE = 1e-9  # added to the normal matrix's diagonal, as fit_normals does
_MIN_CONDITION = 1e-8  # det(A) / (trace(A)/3)^3 below this: too few directions to solve
_UPPER = ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))


def solve_normals_band(lum: npt.NDArray[np.floating] | None, colour: npt.NDArray[np.generic],
                       lights: F64, *,
                       rank_window: tuple[float, float] = RANK_WINDOW,
                       shadow: float = SHADOW_FRACTION, iterations: int = ITERATIONS,
                       estimator: Estimator = "tukey", tuning: float | None = None,
                       tol: float = 1e-4, scale_floor: float = 1e-3,
                       compiled: bool = True, div: float = 1.0,
                       weights: F32 | None = None, albedo: bool = True) -> tuple[F32, F32]:
    r"""Estimate normals and Lambert albedo by robust photometric stereo (Woodham + IRLS).

    Per pixel, with luminance samples :math:`Y_i` under unit lights :math:`l_i`:

    1. **Selection** (as ``fit_normals``): :math:`S` = the samples whose stable rank lies in
       ``[floor(lo·N), ceil(hi·N))`` and with :math:`Y_i > \text{shadow}\cdot\max_j Y_j`; if
       :math:`|S| < 3`, every such non-shadowed sample.  Weights :math:`w_i = [i \in S]`.
    2. **Solve** :math:`g = \arg\min \sum_i w_i (Y_i - g\cdot l_i)^2`, i.e.
       :math:`(\sum w_i l_i l_i^T + 10^{-9} I)\,g = \sum w_i Y_i l_i` (batched 3×3 solves).
    3. **IRLS** (at most ``iterations`` times, pixels with :math:`|S| \ge 3`): residuals
       :math:`r_i = Y_i - g\cdot l_i`, scale
       :math:`\sigma = \max(1.4826\,\mathrm{median}_{i\in S}|r_i|,\ \text{scale\_floor}
       \cdot\max_j Y_j)`, :math:`u_i = r_i/\sigma`, new weights on :math:`S` (0 outside):
       Tukey :math:`w = (1 - (u/c)^2)^2` for :math:`|u| < c`, else 0; Huber
       :math:`w = \min(1, c/|u|)`; then step 2 again.  A pixel stops when
       :math:`|g_{k+1} - g_k| \le \text{tol}\,|g_k|`, or keeps its previous :math:`g, w`
       (and stops) if the new weights leave < 3 samples or an ill-conditioned system.
    4. :math:`n = g/|g|`, flipped so :math:`n_z \ge 0`; :math:`|g| \approx 0` gives
       :math:`(0, 0, 1)`.
    5. Albedo per channel: :math:`\rho_c = \sum w_i I_{ic} s_i / \sum w_i s_i^2`,
       :math:`s_i = \max(0, n\cdot l_i)`, with the final weights.

    ``iterations=0`` is exactly the 0/1-weighted rank-window fit, run by the compiled kernel
    (:mod:`.normals_kernel`, to float32 rounding of this numpy reference) unless
    ``compiled=False``; that kernel also reads ``colour`` 8-/16-bit as decoded, ``colour / div``
    in 0–1 (``div`` 255/65535; the same results).

    Parameters
    ----------
    lum : ndarray, shape (N, P), or None
        Luminance of P pixels under N lights (any consistent units, e.g. 0–1); None: the
        float32 luminance of ``colour`` (float32 or 8-/16-bit) with ``weights``, the values
        of :func:`~.luminance_kernel.luminance_compiled` (the compiled rank window takes it
        chunk by chunk and never stores it whole).
    colour : ndarray, shape (N, P, 3)
        The RGB samples the albedo is fitted to (float32 or float64).
    lights : ndarray, shape (N, 3)
        Unit light directions (x right, y up, z toward the camera); N ≥ 3, not coplanar.
    rank_window : (float, float)
        Fractions ``0 ≤ lo < hi ≤ 1`` of N bounding the kept ranks.
    shadow : float
        Shadow threshold as a fraction of each pixel's brightest sample, ``0 ≤ shadow < 1``.
    iterations : int
        Maximum reweighting steps (≥ 0).
    estimator : {"tukey", "huber"}
        The M-estimator's weight function.
    tuning : float, optional
        Its constant c in units of sigma (default :data:`TUNING`).
    tol : float
        Relative change of g at which a pixel has converged.
    scale_floor : float
        Lower bound of sigma as a fraction of the pixel's brightest sample (> 0), so that
        noise-free data cannot make every residual an outlier.

    Returns
    -------
    normals : ndarray, shape (P, 3), float32
        Unit normals.
    albedo : ndarray, shape (P, 3), float32
        Lambert albedo per channel, in the units of ``colour``; with ``albedo=False`` (a caller
        that only needs the normals), ``(0, 3)`` from the compiled rank window, which then
        skips it (the normals are the same; the numpy path fits it all the same).

    Raises
    ------
    ValueError
        On inconsistent shapes, fewer than 3 or coplanar lights, or out-of-range options.
    """
    like = lum if lum is not None else np.broadcast_to(np.float32(0), colour.shape[:2])
    lights = _check(like, colour, lights, rank_window, shadow, iterations, estimator, tuning,
                    tol, scale_floor)
    n, p = like.shape
    lo, hi = rank_bounds(rank_window, n)
    if compiled and iterations == 0:
        return rank_window_normals(lum, colour, lights, lo, hi, shadow, div, weights, albedo)
    if lum is None:
        if weights is None:
            raise ValueError("lum None needs the luminance weights")
        lum = luminance_compiled(np.ascontiguousarray(colour), np.asarray(weights, np.float32),
                                 1.0 if colour.dtype == np.float32 else div)
    if div != 1.0:
        raise ValueError("colour as decoded (div != 1) needs the compiled rank window")
    c = TUNING[estimator] if tuning is None else float(tuning)
    normals = np.empty((p, 3), np.float32)
    rho = np.empty((p, 3), np.float32)  # with albedo=False too (this path is the reference)
    for p0 in range(0, p, _CHUNK):
        part = slice(p0, min(p, p0 + _CHUNK))
        y = np.ascontiguousarray(np.asarray(lum[:, part], np.float64).T)  # (P, N) rows
        support = _select(y, lo, hi, shadow)
        g, w = _irls(y, support, lights, iterations, estimator, c, tol, scale_floor)
        nrm = _unit(g)
        normals[part] = nrm
        s = np.maximum(_dot(nrm, lights), 0.0)
        ws = w * s
        den = np.maximum((ws * s).sum(axis=1), 1e-12)
        for ch in range(3):
            ic = np.ascontiguousarray(np.asarray(colour[:, part, ch], np.float64).T)
            rho[part, ch] = (ws * ic).sum(axis=1) / den
    return normals, rho


def rank_bounds(rank_window: tuple[float, float], n: int) -> tuple[int, int]:
    """The kept ranks ``[lo, hi)`` of ``n`` samples for a rank window of fractions."""
    return int(np.floor(rank_window[0] * n)), int(np.ceil(rank_window[1] * n))


def check_lights(lights: npt.ArrayLike) -> F64:
    """Return ``lights`` ``(N, 3)`` as float64 if they determine a normal, else ValueError."""
    lf = np.asarray(lights, np.float64)
    if len(lf) < 3 or not np.all(np.isfinite(lf)) or np.linalg.matrix_rank(lf) < 3:
        raise ValueError("photometric stereo needs at least 3 finite, non-coplanar lights")
    return lf


def _check(lum: npt.NDArray[np.floating], colour: npt.NDArray[np.generic], lights: F64,
           rank_window: tuple[float, float], shadow: float, iterations: int, estimator: str,
           tuning: float | None, tol: float, scale_floor: float) -> F64:
    """Validate the arguments; return the lights as float64."""
    if lum.ndim != 2:
        raise ValueError(f"lum must be (N, P), got shape {lum.shape}")
    n, p = lum.shape
    if colour.shape != (n, p, 3):
        raise ValueError(f"colour must be {(n, p, 3)} to match lum, got {colour.shape}")
    if lights.shape != (n, 3):
        raise ValueError(f"{n} samples per pixel but lights of shape {lights.shape}")
    lf = check_lights(lights)
    lo, hi = rank_window
    if not 0.0 <= lo < hi <= 1.0:
        raise ValueError(f"rank_window must satisfy 0 <= lo < hi <= 1, got {rank_window}")
    if not 0.0 <= shadow < 1.0:
        raise ValueError(f"shadow must be in [0, 1), got {shadow}")
    if iterations < 0:
        raise ValueError(f"iterations must be >= 0, got {iterations}")
    if estimator not in TUNING:
        raise ValueError(f"estimator must be one of {sorted(TUNING)}, got {estimator!r}")
    if tuning is not None and not tuning > 0.0:
        raise ValueError(f"tuning must be > 0, got {tuning}")
    if not tol >= 0.0 or not scale_floor > 0.0:
        raise ValueError(f"need tol >= 0 and scale_floor > 0, got {tol}, {scale_floor}")
    return lf


def _select(y: F64, lo: int, hi: int, shadow: float) -> npt.NDArray[np.bool_]:
    """Return the rank-window ∩ non-shadowed samples (all non-shadowed ones if < 3).

    A sample's rank is its position in a stable sort of its row.  From one fast sort:
    values strictly between ``s[lo]`` and ``s[hi-1]`` are in the window, and ties of either
    bound by their order of appearance among the ties (as a stable argsort would rank them).
    """
    lit = y > shadow * y.max(axis=1, keepdims=True)
    s = np.sort(y, axis=1)
    low, high = s[:, lo:lo + 1], s[:, hi - 1:hi]
    window = (y > low) & (y < high)
    for bound in (low, high):
        tie = y == bound
        rank = (y < bound).sum(axis=1, keepdims=True) + np.cumsum(tie, axis=1) - 1
        window |= tie & (rank >= lo) & (rank < hi)
    keep: npt.NDArray[np.bool_] = lit & window
    few = keep.sum(axis=1) < 3
    keep[few] = lit[few]
    return keep


def _dot(g: F64, lights: F64) -> F64:
    """Return ``g·l_i`` as (P, N).  einsum, not BLAS: each row's bits do not depend on P."""
    out: F64 = np.einsum("pk,nk->pn", g, lights)
    return out


def _outer(lights: F64) -> F64:
    """Return the upper-triangle products ``l_i l_j`` of each light, (N, 6)."""
    return np.stack([lights[:, i] * lights[:, j] for i, j in _UPPER], axis=1)


def _solve(w: F64, y: F64, lights: F64) -> tuple[F64, npt.NDArray[np.bool_]]:
    """Solve the weighted normal equations per row; also flag well-conditioned systems."""
    sums = np.einsum("pn,nk->pk", w, _outer(lights))  # (P, 6), no BLAS (see _dot)
    a = np.empty((w.shape[0], 3, 3))
    for k, (i, j) in enumerate(_UPPER):
        a[:, i, j] = a[:, j, i] = sums[:, k]
    det = np.linalg.det(a)
    trace = a[:, 0, 0] + a[:, 1, 1] + a[:, 2, 2]
    well = det > _MIN_CONDITION * (trace / 3.0) ** 3
    a[:, [0, 1, 2], [0, 1, 2]] += _RIDGE
    b = np.einsum("pn,nk->pk", w * y, lights)
    g: F64 = np.linalg.solve(a, b[..., None])[..., 0]
    return g, well


def _weights(u: F64, estimator: str, c: float) -> F64:
    """Return the M-estimator weights of the scaled residuals ``u``."""
    if estimator == "huber":
        out: F64 = c / np.maximum(np.abs(u), c)
        return out
    t = np.clip(1.0 - (u / c) ** 2, 0.0, None)
    return t * t


def _masked_median(x: F64, mask: npt.NDArray[np.bool_], count: npt.NDArray[np.intp]) -> F64:
    """Return each row's median of ``x`` over ``mask`` (``count`` ≥ 1 entries per row)."""
    s = np.sort(np.where(mask, x, np.inf), axis=1)
    lower = np.take_along_axis(s, ((count - 1) // 2)[:, None], axis=1)[:, 0]
    upper = np.take_along_axis(s, (count // 2)[:, None], axis=1)[:, 0]
    out: F64 = 0.5 * (lower + upper)
    return out


def _irls(y: F64, support: npt.NDArray[np.bool_], lights: F64, iterations: int,
          estimator: str, c: float, tol: float, scale_floor: float) -> tuple[F64, F64]:
    """Return g (P, 3) and the final weights (P, N) after at most ``iterations`` steps."""
    w = support.astype(np.float64)
    g, _ = _solve(w, y, lights)
    count = support.sum(axis=1)
    floor = scale_floor * y.max(axis=1)
    active = np.flatnonzero(count >= 3) if iterations else np.empty(0, np.intp)
    for _ in range(iterations):
        if active.size == 0:
            break
        ya, ga, sa = y[active], g[active], support[active]
        r = ya - _dot(ga, lights)
        sigma = np.maximum(MAD_TO_SIGMA * _masked_median(np.abs(r), sa, count[active]),
                           floor[active])
        wa = np.where(sa, _weights(r / sigma[:, None], estimator, c), 0.0)
        gn, well = _solve(wa, ya, lights)
        ok = well & (np.count_nonzero(wa, axis=1) >= 3)
        step = _norm(gn - ga)
        done = step <= tol * _norm(ga)
        g[active[ok]] = gn[ok]
        w[active[ok]] = wa[ok]
        active = active[ok & ~done]
    return g, w


def _norm(v: F64) -> F64:
    """Return the length of each row of ``v`` (P, 3)."""
    out: F64 = np.sqrt(v[:, 0] ** 2 + v[:, 1] ** 2 + v[:, 2] ** 2)
    return out


def _unit(g: F64) -> F64:
    """Return ``g/|g|`` with ``n_z ≥ 0``, and (0, 0, 1) where ``|g|`` is about 0."""
    norm = _norm(g)[:, None]
    good = norm > 1e-12
    nrm = np.where(good, g / np.where(good, norm, 1.0), np.array([0.0, 0.0, 1.0]))
    out: F64 = nrm * np.where(nrm[:, 2:3] < 0, -1.0, 1.0)
    return out
