"""Per-pixel Lambert + isotropic Ward fit with the normal fixed (variable projection).

The model is exactly the viewer's ``svbrdf`` radiance (``docs/rendering.md``, ``E = π`` so kd is
the apparent albedo), in linear RGB::

    cosi = max(0, n·l),  cosr = max(n_z, 1e-4),  h = normalize(l + (0, 0, 1)),
    nh = max(n·h, 1e-4),  tan²θh = (1 − nh²)/nh²,
    I = kd·cosi + ks·exp(−tan²θh/α²)·√(cosi/cosr)/(4α²)

For a fixed α, ``I`` is linear in (kd, ks) per channel, so each α of a log-spaced grid costs one
2×2 solve per pixel shared by the three channels (rti-formats.md §4.3); the α with the smallest
SSE is kept, found coarse to fine (:func:`~.ward_solve.solve_ward_band`).

By default the stack values (0–1, as stored) are taken as ``I``, like the PTM/HSH fits and the
29.0 dB baseline of rti-formats.md, and kd/ks are written ``inputColorSpace: "display"``, which the
viewer shades as they are: :func:`predict_ward` returns ``clamp01(I)``, exactly what it shows.
``lanterna fit --fit-space linear`` decodes the stack to linear light first and writes
``"linear"`` maps (measured on the sRGB JPEG Löwenkopf: 26.8 dB vs 29.3 dB).  See
``docs/fitting.md``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from lanterna.tiler.inputs.stack import StackReader

from .quantise_kernel import unit_bytes
from .ward_kernel import ward_band_compiled
from .ward_solve import MIN_COSI, SATURATED, solve_ward_band, ward_terms

__all__ = ["ALPHA_PER_OCTAVE", "GLOSS_LIMITS", "MIN_COSI", "SATURATED", "Ward", "alpha_grid",
           "fit_ward", "predict_ward", "quantize_ward", "render_ward", "ward_basis"]

#: ``glossLimits`` of the written layer and the range of the α grid.
GLOSS_LIMITS = (0.03, 0.6)
#: α values per halving of α: 1/α² doubles every ``ALPHA_PER_OCTAVE // 2`` steps, the stride
#: of the search's coarse pass, whose lobes the compiled fit squares instead of computing them.
#: (Six until 2026-12-04: the Löwenkopf's leave-one-out PSNR 29.270 → 29.264 dB, the relit
#: coin's 23.578 → 23.593 dB, and the search's time −17 %.)
ALPHA_PER_OCTAVE = 4


def alpha_grid(limits: tuple[float, float] = GLOSS_LIMITS,
               per_octave: int = ALPHA_PER_OCTAVE) -> npt.NDArray[np.float64]:
    """α from the widest to the narrowest: ``lo·2^(j/per_octave)`` for j from the first at or
    above ``hi`` down to 0 (log-spaced, 19 % apart by default; 19 values for (0.03, 0.6)).
    The fit stores the best as its 8-bit gloss level (:func:`~.ward_solve.snap_alpha`)."""
    lo, hi = limits
    top = math.ceil(per_octave * math.log2(hi / lo) - 1e-9)
    grid: npt.NDArray[np.float64] = lo * 2.0 ** (np.arange(top, -1, -1) / per_octave)
    return grid


def ward_basis(normals: npt.NDArray[np.floating], lights: npt.NDArray[np.floating],
               alpha: npt.NDArray[np.floating] | float
               ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """Return the two basis values ``(cosi, ward)`` with ``I = kd·cosi + ks·ward``.

    ``normals`` (..., 3) unit, ``lights`` (N, 3) unit, ``alpha`` scalar or broadcastable to
    ``normals.shape[:-1]``; results have shape ``(N, ...)``.
    """
    cosi, tan2, root = ward_terms(np.asarray(normals, np.float64), np.asarray(lights, np.float64))
    a2 = np.asarray(alpha, np.float64) ** 2
    ward = np.exp(-tan2 / a2) * root / (4.0 * a2)
    return cosi, ward


@dataclass(frozen=True)
class Ward:
    """A fitted Ward layer: normals (H, W, 3) float, and the uint8 maps the viewer reads.

    ``kd``/``ks`` (H, W, 3) linear 0–1 as ``round(255·v)``; ``gloss`` (H, W) with
    ``α = lo + gloss/255·(hi − lo)``, ``(lo, hi) = gloss_limits``.
    """

    normals: npt.NDArray[np.float32]
    kd: npt.NDArray[np.uint8]
    ks: npt.NDArray[np.uint8]
    gloss: npt.NDArray[np.uint8]
    gloss_limits: tuple[float, float] = GLOSS_LIMITS

    def alpha(self) -> npt.NDArray[np.float64]:
        lo, hi = self.gloss_limits
        out: npt.NDArray[np.float64] = lo + self.gloss.astype(np.float64) / 255.0 * (hi - lo)
        return out


def fit_ward(stack: npt.NDArray[np.generic] | StackReader, lights: npt.NDArray[np.floating],
             normals: npt.NDArray[np.floating], *, alphas: npt.NDArray[np.float64] | None = None,
             gloss_limits: tuple[float, float] = GLOSS_LIMITS, band_rows: int = 32,
             compiled: bool = True, div: float = 1.0
             ) -> tuple[npt.NDArray[np.float32], npt.NDArray[np.float32], npt.NDArray[np.float32]]:
    """Fit Lambert + isotropic Ward per pixel with the normal fixed.

    Parameters
    ----------
    stack : ndarray, shape (N, H, W, 3)
        Float 0–1, taken as linear radiance as stored (see the module docstring), or a
        :class:`~lanterna.tiler.inputs.stack.StackReader` read band by band.
    lights : ndarray, shape (N, 3)
        Unit light directions.
    normals : ndarray, shape (H, W, 3)
        Unit normals (x right, y up, z toward the camera).
    alphas : ndarray, shape (A,), optional
        α grid, tried in order (default :func:`alpha_grid`).
    gloss_limits : (lo, hi)
        The layer's ``glossLimits``: the best α is stored as the α of its 8-bit gloss level.

    Returns
    -------
    kd, ks : ndarray, shape (H, W, 3), float32, linear, ``kd ≥ 0``, ``ks ≥ 0``
    alpha : ndarray, shape (H, W), float32, the α of a gloss level (what the layer stores)

    ``ks`` is capped at 1 (the stored range), with kd refitted for the capped value.
    Samples with ``n·l < MIN_COSI`` or any channel ``≥ SATURATED`` are excluded.  Per α, the
    per-pixel normal equations ``[[Σaa, Σab], [Σab, Σbb]]·(kd_c, ks_c) = (Σa·y_c, Σb·y_c)``
    (``a = cosi``, ``b`` the Ward term) are solved for the three channels at once; the ks
    colour is then kept within ``MAX_SPECULAR_ANGLE`` of the grey–diffuse cone (else projected
    onto it), an α is tried only where ``MIN_LOBE_SAMPLES`` samples lie in its lobe, and a channel
    whose kd would be negative gets ``kd = 0`` and its ks alone (:mod:`.ward_solve`).  The
    best α is then moved to its gloss level's α, and kd, ks solved again there where the pixel
    has a specular term, so the maps fit the α the viewer reads.  Rows are processed in bands
    of ``band_rows``, so temporaries are ``O(N·band·W)``.
    ``compiled`` runs the Numba kernel (:mod:`.ward_kernel`), else the numpy reference.  With
    ``div`` ≠ 1 (compiled only), ``stack`` is 8-/16-bit as decoded: ``stack / div`` is the 0–1
    stack, with the same results.
    """
    n, h, w, _ = stack.shape
    if lights.shape != (n, 3) or normals.shape != (h, w, 3):
        raise ValueError(f"stack {stack.shape}, lights {lights.shape}, normals {normals.shape}")
    grid = alpha_grid() if alphas is None else np.asarray(alphas, np.float64)
    lf = np.asarray(lights, np.float64)
    if compiled and h <= band_rows:  # one band: the kernel's own maps (no copies)
        return ward_band_compiled(np.asarray(stack[:, 0:h]), normals, lf, grid, gloss_limits,
                                  div)
    kd_out = np.empty((h, w, 3), np.float32)
    ks_out = np.empty((h, w, 3), np.float32)
    al_out = np.empty((h, w), np.float32)
    for y0 in range(0, h, band_rows):
        nrm = normals[y0:y0 + band_rows]
        b = nrm.shape[0]
        maps: tuple[npt.NDArray[np.floating], ...]
        if compiled:  # (N, b, W, 3) as decoded or float32, the kernel's input
            maps = ward_band_compiled(np.asarray(stack[:, y0:y0 + b]), nrm, lf, grid,
                                      gloss_limits, div)
        else:
            if div != 1.0:
                raise ValueError("the numpy reference takes a float stack")
            maps = solve_ward_band(np.asarray(stack[:, y0:y0 + b], np.float64),
                                   np.asarray(nrm, np.float64), lf, grid, gloss_limits)
        kd_out[y0:y0 + b], ks_out[y0:y0 + b], al_out[y0:y0 + b] = maps
    return kd_out, ks_out, al_out


def quantize_ward(normals: npt.NDArray[np.floating], kd: npt.NDArray[np.floating],
                  ks: npt.NDArray[np.floating], alpha: npt.NDArray[np.floating],
                  gloss_limits: tuple[float, float] = GLOSS_LIMITS) -> Ward:
    """Quantise the fitted maps to the uint8 layer maps (kd/ks linear 0–1, gloss via limits)."""
    lo, hi = gloss_limits
    return Ward(np.asarray(normals, np.float32), unit_bytes(kd), unit_bytes(ks),
                unit_bytes(alpha, lo, hi), (lo, hi))


def render_ward(normals: npt.NDArray[np.floating], kd: npt.NDArray[np.floating],
                ks: npt.NDArray[np.floating], alpha: npt.NDArray[np.floating],
                light: npt.NDArray[np.floating]) -> npt.NDArray[np.float64]:
    """Return the linear radiance ``I`` (H, W, 3) of the viewer's Ward model under ``light``."""
    cosi, ward = ward_basis(normals, np.asarray(light, np.float64)[None], alpha)
    out: npt.NDArray[np.float64] = (np.asarray(kd, np.float64) * cosi[0][..., None]
                                    + np.asarray(ks, np.float64) * ward[0][..., None])
    return out


def predict_ward(model: Ward, light: npt.NDArray[np.float64]) -> npt.NDArray[np.float32]:
    """Return ``clamp01(I)`` (H, W, 3) from the stored uint8 maps, as the viewer evaluates it."""
    radiance = render_ward(model.normals, model.kd / 255.0, model.ks / 255.0, model.alpha(), light)
    return np.clip(radiance, 0.0, 1.0).astype(np.float32)
