"""Per-row-band solvers of every fittable model, and their predictions on the float result.

Every model is per pixel, so a fit is the concatenation of the fits of its row bands: these
functions take one band ``(N, b, W, 3)`` float32 in 0–1 (all lights) and return the band's
float outputs; the whole-image fitters (:mod:`~lanterna.tiler.fit.models`,
:mod:`~lanterna.tiler.fit.ptm`, :mod:`~lanterna.tiler.fit.hsh`) and the streaming engine
(:mod:`~lanterna.tiler.fit.engine`) both loop over them, so they cannot disagree.
"""

from __future__ import annotations

from typing import cast

import numpy as np
import numpy.typing as npt

from lanterna.tiler.formats.hsh_basis import hsh_weights
from lanterna.tiler.formats.ptm_model import ptm_weights

from .compiled import SAMPLE_TYPES
from .linear_kernel import linear_band
from .lrgb_kernel import lrgb_band_compiled
from .luminance_kernel import luminance_compiled
from .normals import (
    ITERATIONS,
    RANK_WINDOW,
    SHADOW_FRACTION,
    rank_bounds,
    solve_normals_band,
)
from .normals_held_out_kernel import rank_window_normals_held_out
from .ward import GLOSS_LIMITS, Ward, fit_ward, predict_ward, quantize_ward

Band = npt.NDArray[np.float32]
Lights = npt.NDArray[np.float64]
Out = dict[str, npt.NDArray[np.generic]]

#: Rec. 709 luminance weights used by ptmfit (``computepoly.c``).
LUMINANCE_WEIGHTS = (0.2125, 0.7154, 0.0721)
_WEIGHTS32: npt.NDArray[np.float32] = np.asarray(LUMINANCE_WEIGHTS, np.float32)
#: Tukey IRLS steps of the photometric stereo in linear light (none on values as stored).
IRLS_ITERATIONS = ITERATIONS


def _project(pinv: npt.NDArray[np.float32], band: Band) -> npt.NDArray[np.float32]:
    """``(K, N) @ (N, b, W, 3)``, returned ``(b, W, 3, K)`` (a view): the compiled product the
    streamed fit makes (:func:`~.linear_kernel.linear_band`), so whole-image and streamed fits
    agree bit for bit."""
    n, b, w, c = band.shape
    flat = np.ascontiguousarray(band, np.float32).reshape(n, -1)
    out = np.empty((pinv.shape[0], flat.shape[1]), np.float32)
    linear_band(flat, 1.0, np.asarray(pinv, np.float32), out)
    return np.moveaxis(out.reshape(-1, b, w, c), 0, -1)


def ptm_rgb_band(band: Band, pinv255: npt.NDArray[np.float32]) -> Out:
    """RGB PTM: ``coeffs (b, W, 3, 6)`` in 0–255 units, ``pinv255`` the ``(6, N)`` pinv × 255."""
    return {"coeffs": _project(pinv255, band)}


def luminance(band: npt.NDArray[np.generic], div: float = 1.0) -> npt.NDArray[np.float32]:
    """``Y`` of every sample of ``band (…, 3)`` in float32 (:data:`LUMINANCE_WEIGHTS`):
    compiled (:mod:`.luminance_kernel`) for a float32 band, or 8-/16-bit as decoded
    (``band / div`` in 0–1: the same values), a strided one copied first, so the rounding is
    always ``(r·w0 + g·w1) + b·w2`` (numpy's ``band @ weights`` rounds as its BLAS does: one
    ulp away on CPUs where it fuses multiply-adds, which made an in-memory fit, whose bands
    are strided, differ from the streamed one).  A float64 band: numpy's product, float64."""
    if band.dtype in SAMPLE_TYPES and band.shape[-1:] == (3,):
        return luminance_compiled(np.ascontiguousarray(band), _WEIGHTS32,
                                  1.0 if band.dtype == np.float32 else div)
    if div != 1.0:
        raise ValueError(f"a {band.dtype} band is read as decoded only when 8-/16-bit")
    return cast("npt.NDArray[np.float32]", cast("npt.NDArray[np.floating]", band) @ _WEIGHTS32)


def ptm_lrgb_band(band: npt.NDArray[np.generic], pinv: npt.NDArray[np.float32], *,
                  compiled: bool = True, div: float = 1.0) -> Out:
    """LRGB PTM (ptmfit): ``coeffs (b, W, 6)`` 0–255 units of the normalised luminance and
    ``rgb (b, W, 3)`` uint8 = ``rint(255 · Σ c·Yn / Σ Yn²)`` (:mod:`.lrgb_kernel`, which also
    reads a band as decoded, ``band / div``; ``compiled`` False: this numpy reference, of a
    float band)."""
    if compiled:
        coeffs32, rgb8 = lrgb_band_compiled(band, pinv, LUMINANCE_WEIGHTS, div)
        return {"coeffs": coeffs32, "rgb": rgb8}
    band = np.asarray(band, np.float32) / np.float32(div)
    n, b, w, _ = band.shape
    lum = luminance(band)  # (N, b, W)
    peak = lum.max(axis=0)
    safe = np.where(peak > 1e-6, peak, np.float32(1.0))
    lum_n = np.where(peak > 1e-6, lum / safe, np.float32(0.0))
    coeffs = (pinv @ (lum_n.reshape(n, -1) * np.float32(255.0))).T.reshape(b, w, 6)
    energy = np.einsum("nhw,nhw->hw", lum_n, lum_n)
    proj = np.einsum("nhwc,nhw->hwc", band, lum_n)
    colour = proj / np.where(energy > 1e-12, energy, np.float32(1.0))[..., None]
    rgb = np.clip(np.rint(colour * 255.0), 0, 255).astype(np.uint8)
    return {"coeffs": coeffs.astype(np.float32), "rgb": rgb}


def hsh_band(band: Band, pinv: npt.NDArray[np.float32]) -> Out:
    """HSH: ``coeffs (b, W, 3, T)`` in 0–1 units, ``pinv`` the ``(T, N)`` pseudo-inverse."""
    return {"coeffs": _project(pinv, band)}


def normals_band(band: npt.NDArray[np.generic], lights: Lights, *,
                 rank_window: tuple[float, float] = RANK_WINDOW,
                 shadow: float = SHADOW_FRACTION, iterations: int = 0, div: float = 1.0,
                 albedo: bool = True) -> Out:
    """Robust photometric stereo: ``normals (b, W, 3)`` unit, ``albedo (b, W, 3)`` (not with
    ``albedo=False``: the normals alone, as a Ward fit needs them).

    The rank-window selection of :func:`lanterna.tiler.fit.models.fit_normals`, refined by
    ``iterations`` steps of Tukey IRLS (:func:`~lanterna.tiler.fit.normals.solve_normals_band`;
    0 = the rank window alone, the default for values as stored).  ``band / div`` is the 0–1
    band (``div`` ≠ 1: 8-/16-bit as decoded, contiguous, with the rank window alone).
    """
    n, b, w, _ = band.shape
    # None: the solver takes the luminance itself (the rank window chunk by chunk, not stored)
    lum = None if band.dtype in SAMPLE_TYPES else luminance(band, div).reshape(n, -1)
    nrm, rho = solve_normals_band(lum, band.reshape(n, -1, 3), lights.astype(np.float64),
                                  rank_window=rank_window, shadow=shadow, iterations=iterations,
                                  div=div, weights=_WEIGHTS32, albedo=albedo)
    if not albedo:
        return {"normals": nrm.reshape(b, w, 3)}
    return {"normals": nrm.reshape(b, w, 3), "albedo": rho.reshape(b, w, 3)}


def normals_band_held_out(band: npt.NDArray[np.generic], lights: Lights,
                          train: npt.NDArray[np.intp], held: npt.NDArray[np.intp], div: float = 1.0
                          ) -> tuple[Out, npt.NDArray[np.float64]]:
    """:func:`normals_band` (the rank window, values as stored) and, in the same pass, the
    squared errors on the ``held`` lights of the same fit of the ``train`` lights
    (:mod:`.normals_held_out_kernel`); at most ``MAX_LIGHTS`` lights; ``band / div`` in 0–1."""
    n, b, w, _ = band.shape
    lum = None if band.dtype in SAMPLE_TYPES else luminance(band, div).reshape(n, -1)
    nrm, albedo, sse = rank_window_normals_held_out(
        lum, band.reshape(n, -1, 3), lights.astype(np.float64), rank_bounds(RANK_WINDOW, n),
        SHADOW_FRACTION, train, held, rank_bounds(RANK_WINDOW, len(train)), div, _WEIGHTS32)
    return {"normals": nrm.reshape(b, w, 3), "albedo": albedo.reshape(b, w, 3)}, sse


def ward_band(band: npt.NDArray[np.generic], lights: Lights, normals: npt.NDArray[np.float32],
              div: float = 1.0) -> Out:
    """Lambert + Ward with the normal fixed: uint8 ``kd``, ``ks``, ``gloss`` (b, W[, 3]);
    ``band / div`` in 0–1."""
    kd, ks, alpha = fit_ward(band, lights, normals, band_rows=max(1, band.shape[1]), div=div)
    ward = quantize_ward(normals, kd, ks, alpha)
    return {"kd": ward.kd, "ks": ward.ks, "gloss": ward.gloss}


def predict_ptm_band(out: Out, light: npt.NDArray[np.float64]) -> Band:
    """A PTM band (float coefficients) relit under ``light``, 0–1 as ``Ptm.relight``."""
    w = ptm_weights(float(light[0]), float(light[1])).astype(np.float32)
    lum = np.asarray(out["coeffs"], np.float32) @ w
    if "rgb" in out:
        res = out["rgb"].astype(np.float32) / 255.0 * (lum / 255.0)[..., None]
    else:
        res = lum / 255.0
    return np.clip(res, 0.0, 1.0).astype(np.float32)


def predict_hsh_band(out: Out, light: npt.NDArray[np.float64]) -> Band:
    """An HSH band (float coefficients) relit under ``light``, clipped to 0–1."""
    terms = out["coeffs"].shape[-1]
    wts = hsh_weights(float(light[0]), float(light[1]), terms)
    res: Band = np.clip(np.asarray(out["coeffs"], np.float32) @ wts, 0.0, 1.0).astype(np.float32)
    return res


def predict_normals_band(out: Out, light: npt.NDArray[np.float64]) -> Band:
    """Lambert ``albedo · max(0, n·l)`` of a normals band, clipped to 0–1."""
    shade = np.maximum(np.asarray(out["normals"], np.float32) @ light.astype(np.float32), 0.0)
    return np.clip(out["albedo"] * shade[..., None], 0.0, 1.0).astype(np.float32)


def predict_ward_band(out: Out, light: npt.NDArray[np.float64]) -> Band:
    """The viewer's ``clamp01(I)`` of a Ward band from its stored uint8 maps."""
    ward = Ward(out["normals"].astype(np.float32), out["kd"].astype(np.uint8),
                out["ks"].astype(np.uint8), out["gloss"].astype(np.uint8), GLOSS_LIMITS)
    return predict_ward(ward, light)
