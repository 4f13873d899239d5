"""HSH layers (``layerType: "hsh"``, 4, 9 or 16 terms) in the reference renderer.

The per-light weights come from :func:`lanterna.tiler.formats.hsh_basis.hsh_weights`;
:func:`hsh_basis` is the same basis over arrays of directions (for the albedo, lit along each
pixel's normal).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np
import numpy.typing as npt

from lanterna.tiler.formats.hsh_basis import MAX_THETA, hsh_weights

from .filters import f3, unsharp
from .shading import F32, Light, Params, Surface, clamp01, dot3, f32, mean_rgb

#: The three lights of the HSH normal estimate: θ = 45°, φ = 30°, 150°, 270°.
NORMAL_LIGHTS = np.array(
    [[math.sin(math.pi / 4) * math.cos(math.radians(p)),
      math.sin(math.pi / 4) * math.sin(math.radians(p)), math.cos(math.pi / 4)]
     for p in (30.0, 150.0, 270.0)], np.float32)


def hsh_basis(lu: npt.ArrayLike, lv: npt.ArrayLike, terms: int) -> F32:
    """HSH weights for arrays of projected directions, float32 ``broadcast(lu, lv) + (terms,)``.

    ``lz = √(1 − lu² − lv²)``, ``θ = min(acos(lz), π/2 − 0.04)``, ``x = cos θ``,
    ``s = √(x − x²)``; ``(cos φ, sin φ) = (lu, lv)/r``, or ``(1, 0)`` where ``r < 1e-6``.
    """
    if terms not in (4, 9, 16):
        raise ValueError(f"HSH has 4, 9 or 16 terms, not {terms}")
    u, v = np.broadcast_arrays(np.asarray(lu, np.float32), np.asarray(lv, np.float32))
    one = np.float32(1)
    r2 = u * u + v * v
    lz = np.sqrt(np.maximum(np.float32(0), one - r2))
    theta = np.minimum(np.arccos(np.clip(lz, 0, 1)), np.float32(MAX_THETA))
    x = np.cos(theta).astype(np.float32)
    s = np.sqrt(np.maximum(x - x * x, np.float32(0)))
    r = np.sqrt(r2)
    tiny = r < np.float32(1e-6)
    rs = np.where(tiny, one, r)
    cp = np.where(tiny, one, u / rs).astype(np.float32)
    sp = np.where(tiny, np.float32(0), v / rs).astype(np.float32)
    c2, s2 = cp * cp - sp * sp, 2 * sp * cp
    c3, s3 = 4 * cp**3 - 3 * cp, 3 * sp - 4 * sp**3
    pi = math.pi

    def k(value: float) -> np.float32:
        return np.float32(value)

    x2x = x * x - x
    quad = 1 - 5 * x + 5 * x * x
    w = [
        np.full_like(x, k(1 / math.sqrt(2 * pi))),
        k(math.sqrt(6 / pi)) * cp * s,
        k(math.sqrt(3 / (2 * pi))) * (2 * x - 1),
        k(math.sqrt(6 / pi)) * sp * s,
        k(math.sqrt(30 / pi)) * c2 * x2x,
        k(math.sqrt(30 / pi)) * cp * (2 * x - 1) * s,
        k(math.sqrt(5 / (2 * pi))) * (6 * x * x - 6 * x + 1),
        k(math.sqrt(30 / pi)) * sp * (2 * x - 1) * s,
        k(math.sqrt(30 / pi)) * s2 * x2x,
        k(2 * math.sqrt(35 / pi)) * c3 * s**3,
        k(math.sqrt(210 / pi)) * c2 * (2 * x - 1) * x2x,
        k(2 * math.sqrt(21 / pi)) * cp * s * quad,
        k(math.sqrt(7 / (2 * pi))) * (20 * x**3 - 30 * x * x + 12 * x - 1),
        k(2 * math.sqrt(21 / pi)) * sp * s * quad,
        k(math.sqrt(210 / pi)) * s2 * (2 * x - 1) * x2x,
        k(2 * math.sqrt(35 / pi)) * s3 * s**3,
    ]
    out: F32 = np.stack(w[:terms], axis=-1).astype(np.float32)
    return out


def hsh_coefficients(layer: Mapping[str, Any], channels: Mapping[str, F32]) -> F32:
    """Stack an HSH layer's channels ``R{k}, G{k}, B{k}`` into ``(H, W, 3, K)``."""
    terms = int(layer["terms"])
    return np.stack([np.stack([channels[f"{c}{k}"] for k in range(terms)], axis=-1)
                     for c in "RGB"], axis=-2).astype(np.float32)


def hsh_normals(coeffs: npt.ArrayLike) -> F32:
    """Return HSH normals (RTIViewer/OpenLIME) as docs/rendering.md defines them.

    The field is relit (unclamped) under three lights at θ = 45°, φ = 30°, 150°, 270°;
    ``I_i = r + g + b``, ``g = M⁻¹·I`` with ``M`` the matrix of rows ``l_i``, ``n = g/‖g‖``
    (``(0, 0, 1)`` where ``‖g‖ < 1e-6``).

    Parameters
    ----------
    coeffs:
        ``(..., 3, K)`` dequantised coefficients (channel R, G, B; K = 4, 9 or 16), e.g.
        :meth:`lanterna.tiler.formats.hsh_model.Hsh.dequantized`.

    Returns
    -------
    numpy.ndarray
        ``(..., 3)`` float32 unit normals (x right, y up, z to the viewer).
    """
    a = np.asarray(coeffs, np.float32)
    if a.ndim < 2 or a.shape[-2] != 3 or a.shape[-1] not in (4, 9, 16):
        raise ValueError(f"HSH coefficients must be (..., 3, 4|9|16), got {a.shape}")
    terms = a.shape[-1]
    total = np.sum(a, axis=-2, dtype=np.float32)  # r + g + b is linear in the coefficients
    weights = np.stack([hsh_weights(float(lu), float(lv), terms)
                        for lu, lv, _ in NORMAL_LIGHTS], axis=0)  # (3 lights, K)
    return normals_from_relights(np.einsum("...k,ik->...i", total, weights).astype(np.float32))


def normals_from_relights(intensities: npt.ArrayLike) -> F32:
    """``n = g/‖g‖``, ``g = M⁻¹·I``, from the ``(..., 3)`` brightness ``I_i`` of a pixel relit
    under each of :data:`NORMAL_LIGHTS` (``M`` their rows); ``(0, 0, 1)`` where ``‖g‖ < 1e-6``."""
    m_inv = np.linalg.inv(NORMAL_LIGHTS.astype(np.float64)).astype(np.float32)
    g = np.einsum("ij,...j->...i", m_inv, np.asarray(intensities, np.float32)).astype(np.float32)
    length = np.sqrt(dot3(g, g))[..., None]
    n = g / np.where(length > 0, length, np.float32(1))
    out: F32 = np.where(length >= np.float32(1e-6), n,
                        np.array([0, 0, 1], np.float32)).astype(np.float32)
    return out


def hsh_color(coeffs: F32, weights: npt.ArrayLike, intensity: float = 1.0) -> F32:
    """The colour mode's unclamped ``c = Σ_k a_{c,k}·w_k·I`` of ``(..., 3, K)`` coefficients.

    ``weights`` are one light's ``(K,)`` weights, or ``(..., K)`` per pixel.
    """
    w = np.asarray(weights, np.float32)[..., None, :]
    return f32(np.sum(coeffs * w, axis=-1, dtype=np.float32) * np.float32(intensity))


def hsh_surface(layer: Mapping[str, Any], channels: Mapping[str, F32]) -> Surface:
    """Build the :class:`~.shading.Surface` of an HSH layer from its dequantised channels."""
    return basis_surface(layer, channels, hsh_normals, hsh_weights, hsh_basis)


def basis_surface(layer: Mapping[str, Any], channels: Mapping[str, F32],
                  normals: Callable[[F32], F32], weights: Callable[[float, float, int], Any],
                  basis: Callable[[Any, Any, int], Any]) -> Surface:
    """The :class:`~.shading.Surface` of a layer of per-channel coefficients of a light basis in
    HSH's channel layout (HSH, Relight's sh): its ``normals`` from the coefficients, colour
    under a light from the basis's ``weights`` (one light) and albedo from its ``basis``
    evaluated at each pixel's normal (arrays of light directions)."""
    a = hsh_coefficients(layer, channels)
    terms = a.shape[-1]
    n = normals(a)

    def color(light: Light) -> F32:
        return hsh_color(a, weights(light.lu, light.lv, terms), light.intensity)

    albedo = f32(np.sum(a * basis(n[..., 0], n[..., 1], terms)[..., None, :], axis=-1,
                        dtype=np.float32))
    return Surface(color=color, normal=n, albedo=albedo, special=hsh_special_modes(color, n))


def hsh_special_modes(color: Callable[[Light], F32], n: F32
                      ) -> dict[str, Callable[[Light, Params], F32]]:
    """HSH's own ``specular`` and ``unsharpCoefficients`` for a colour function and normals.

    Shared by every layer whose colour is linear in its coefficients (HSH, the PCA bases):
    ``c·specKd + mean(c)·specKs·4·s`` with ``s = clamp01(n·h)^(specExponent/5)``, and the
    unsharp mask of the colour (filtering the coefficients then relighting is the same).
    """

    def specular(light: Light, p: Params) -> F32:
        s = np.power(clamp01(dot3(n, light.h)), np.float32(p["specExponent"] / 5.0))[..., None]
        c = color(light)
        kd, ks = np.float32(p["specKd"]), np.float32(p["specKs"])
        return (c * kd + mean_rgb(c)[..., None] * ks * np.float32(4) * s).astype(np.float32)

    def unsharp_coefficients(light: Light, p: Params) -> F32:
        c = color(light)
        return unsharp(c, f3(c), p["umGain"])

    return {"specular": specular, "unsharpCoefficients": unsharp_coefficients}
