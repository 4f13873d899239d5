"""PCA layers (``layerType: "rbf"`` and ``"bilinear"``, colour spaces ``mrgb``/``mycc``).

The relighting itself is :class:`lanterna.tiler.formats.pca_model.PcaBasis`: for a light it
gives the folded RGB plane weights ``W`` ``(N + 1, 3)`` and the colour of a pixel with
coefficients ``r`` (channels ``P0 … P{N−1}``) is ``c = W[0] + Σ_q r_q·W[q + 1]``
(docs/rendering.md, "rbf" and "bilinear"). The shape comes from three fixed relights, HSH's
:data:`~.hsh.NORMAL_LIGHTS`, whose weights are computed once per layer.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
import numpy.typing as npt

from lanterna.tiler.formats.pca_model import PcaBasis

from .hsh import NORMAL_LIGHTS, hsh_special_modes, normals_from_relights
from .shading import F32, Light, Surface, dot3, f32

#: Smallest Lambertian denominator ``Σ_i l_i·n`` of the albedo (grazing normals).
MIN_ALBEDO_COSINE = 0.1


def pca_coefficients(basis: PcaBasis, channels: Mapping[str, F32]) -> F32:
    """Stack a PCA layer's dequantised channels ``P0 … P{N−1}`` into ``(H, W, N)`` float32."""
    missing = [f"P{q}" for q in range(basis.nplanes) if f"P{q}" not in channels]
    if missing:
        raise ValueError(f"{basis.layer_type} layer: channels {', '.join(missing)} are missing")
    return np.stack([channels[f"P{q}"] for q in range(basis.nplanes)], axis=-1).astype(
        np.float32)


def pca_color(r: F32, weights: npt.ArrayLike, intensity: float = 1.0) -> F32:
    """``(W[0] + Σ_q r_q·W[q + 1])·intensity`` of ``(..., N)`` coefficients, ``(..., 3)``."""
    w = np.asarray(weights, np.float32)
    c = w[0] + np.einsum("...q,qk->...k", r, w[1:], dtype=np.float32)
    return f32(c * np.float32(intensity))


def pca_normals(relit: F32) -> F32:
    """Normals from the colours ``(3, ..., 3)`` relit under :data:`~.hsh.NORMAL_LIGHTS`.

    ``I_i = r + g + b`` of the ``i``-th relight, ``g = M⁻¹·I`` (``M`` the rows ``l_i``),
    ``n = g/‖g‖``, ``(0, 0, 1)`` where ``‖g‖ < 1e-6`` (as HSH's).
    """
    return normals_from_relights(np.moveaxis(f32(np.sum(relit, axis=-1, dtype=np.float32)),
                                             0, -1))


def pca_albedo(relit: F32, n: F32) -> F32:
    """Lambertian ``ρ = Σ_i c(l_i) / max(Σ_i l_i·n, 0.1)`` of the three normal relights."""
    total = np.sum(relit, axis=0, dtype=np.float32)
    cosine = dot3(n, np.sum(NORMAL_LIGHTS, axis=0, dtype=np.float32))
    return f32(total / np.maximum(cosine, np.float32(MIN_ALBEDO_COSINE))[..., None])


def pca_surface(layer: Mapping[str, Any], channels: Mapping[str, F32]) -> Surface:
    """Build the :class:`~.shading.Surface` of an ``rbf`` or ``bilinear`` layer."""
    basis = PcaBasis.from_block(layer)
    r = pca_coefficients(basis, channels)
    relit = np.stack([pca_color(r, basis.weights(float(lu), float(lv)))
                      for lu, lv, _ in NORMAL_LIGHTS], axis=0)
    n = pca_normals(relit)

    def color(light: Light) -> F32:
        return pca_color(r, basis.weights(light.lu, light.lv), light.intensity)

    return Surface(color=color, normal=n, albedo=pca_albedo(relit, n),
                   special=hsh_special_modes(color, n))
