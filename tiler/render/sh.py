"""Relight's plain spherical harmonics (``layerType: "sh"``, 4 or 9 terms) in the reference.

The light basis is :func:`lanterna.tiler.formats.sh_model.sh_basis` (docs/rendering.md, "sh").
Everything else is HSH's (:mod:`.hsh`), with that basis in place of the hemispherical one: the
same channels ``R{k}, G{k}, B{k}``, the colour ``c = Σ_k a_{c,k}·Y_k(l)·I``, the normal from three
fixed relights (:data:`~.hsh.NORMAL_LIGHTS`), the albedo relit along each pixel's normal, and
HSH's ``specular`` and ``unsharpCoefficients``.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
import numpy.typing as npt

from lanterna.tiler.formats.sh_model import SH_TERMS, sh_basis, sh_weights

from .hsh import NORMAL_LIGHTS, basis_surface, normals_from_relights
from .shading import F32, Surface


def sh_normals(coeffs: npt.ArrayLike) -> F32:
    """Unit normals ``(..., 3)`` of ``(..., 3, K)`` SH coefficients, estimated as HSH's
    (:func:`~.hsh.hsh_normals`): ``I_i = r + g + b`` relit under :data:`~.hsh.NORMAL_LIGHTS`,
    ``n = M⁻¹·I / ‖M⁻¹·I‖``."""
    a = np.asarray(coeffs, np.float32)
    if a.ndim < 2 or a.shape[-2] != 3 or a.shape[-1] not in SH_TERMS:
        raise ValueError(f"SH coefficients must be (..., 3, 4|9), got {a.shape}")
    total = np.sum(a, axis=-2, dtype=np.float32)
    weights = sh_basis(NORMAL_LIGHTS[:, 0], NORMAL_LIGHTS[:, 1], a.shape[-1])  # (3 lights, K)
    return normals_from_relights(np.einsum("...k,ik->...i", total, weights).astype(np.float32))


def sh_surface(layer: Mapping[str, Any], channels: Mapping[str, F32]) -> Surface:
    """Build the :class:`~.shading.Surface` of an sh layer from its dequantised channels: HSH's,
    with the SH basis."""
    return basis_surface(layer, channels, sh_normals, sh_weights, sh_basis)
