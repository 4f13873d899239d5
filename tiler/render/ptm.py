"""PTM layers (``layerType: "ptm"``, lrgb and rgb) in the reference renderer (docs/rendering.md).

Coefficients are in display units (``a/255`` of the HP PTM convention, i.e. the dequantised
channels ``L0…L5`` or ``R0…B5``), basis ``w = [lu², lv², lu·lv, lu, lv, 1]``.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
import numpy.typing as npt

from .filters import f3, f5, unsharp
from .shading import F32, Light, Params, Surface, clamp01, dot3, f32, grey, mean_rgb

_UP = (0.0, 0.0, 1.0)


def ptm_basis(lu: npt.ArrayLike, lv: npt.ArrayLike) -> F32:
    """Basis ``[lu², lv², lu·lv, lu, lv, 1]`` in float32, shape ``broadcast(lu, lv) + (6,)``."""
    u, v = np.broadcast_arrays(np.asarray(lu, np.float32), np.asarray(lv, np.float32))
    out: F32 = np.stack([u * u, v * v, u * v, u, v, np.ones_like(u)], axis=-1).astype(np.float32)
    return out


def ptm_coefficients(layer: Mapping[str, Any], channels: Mapping[str, F32]) -> F32:
    """Stack a PTM layer's channels: lrgb ``(H, W, 6)`` (L0…L5), rgb ``(H, W, 3, 6)``."""
    if layer.get("colorspace") == "lrgb":
        return np.stack([channels[f"L{k}"] for k in range(6)], axis=-1).astype(np.float32)
    if layer.get("colorspace") == "rgb":
        return np.stack([np.stack([channels[f"{c}{k}"] for k in range(6)], axis=-1)
                         for c in "RGB"], axis=-2).astype(np.float32)
    raise ValueError(f"unknown PTM colorspace {layer.get('colorspace')!r}")


def _set_normals(a: F32) -> F32:
    """Malzbender's normal of each ``(..., 6)`` coefficient set, ``(..., 3)``."""
    a0, a1, a2, a3, a4 = (a[..., k] for k in range(5))
    d = np.float32(4) * a0 * a1 - a2 * a2
    ok = (d > 0) & (a0 < 0)
    safe = np.where(ok, d, np.float32(1)).astype(np.float32)
    lu = np.where(ok, (a2 * a4 - np.float32(2) * a1 * a3) / safe, np.float32(0))
    lv = np.where(ok, (a2 * a3 - np.float32(2) * a0 * a4) / safe, np.float32(0))
    r = np.sqrt(lu * lu + lv * lv)
    outside = r > 1
    rs = np.where(outside, r, np.float32(1)).astype(np.float32)
    lu, lv = (lu / rs).astype(np.float32), (lv / rs).astype(np.float32)
    lz = np.sqrt(np.maximum(np.float32(0), np.float32(1) - lu * lu - lv * lv))
    out: F32 = np.stack([lu, lv, lz], axis=-1).astype(np.float32)
    return out


def ptm_normals(coeffs: npt.ArrayLike) -> F32:
    """Return PTM normals (Malzbender 2001) as docs/rendering.md defines them.

    Parameters
    ----------
    coeffs:
        ``(..., 6)`` luminance coefficients (lrgb), or ``(..., 3, 6)`` per-channel coefficients
        (rgb; give at least 2 leading dimensions, e.g. ``(H, W, 3, 6)``).

    Returns
    -------
    numpy.ndarray
        ``(..., 3)`` float32 unit normals (x right, y up, z to the viewer). Where
        ``d = 4a0a1 − a2²`` is not positive or ``a0 >= 0`` the set's normal is ``(0, 0, 1)``; a
        maximum outside the unit disk is projected onto its rim. For rgb the three channel
        normals are averaged and normalised (``(0, 0, 1)`` where the average vanishes).
    """
    a = np.asarray(coeffs, np.float32)
    if a.shape[-1:] != (6,):
        raise ValueError(f"PTM coefficients must end in 6 terms, got {a.shape}")
    if a.ndim >= 4 and a.shape[-2] == 3:
        avg = f32(np.mean(_set_normals(a), axis=-2, dtype=np.float32))
        length = np.sqrt(dot3(avg, avg))[..., None]
        n = avg / np.where(length > 0, length, np.float32(1))
        out: F32 = np.where(length > np.float32(1e-6), n, np.asarray(_UP, np.float32)).astype(
            np.float32)
        return out
    return _set_normals(a)


def evaluate(coeffs: F32, weights: F32) -> F32:
    """``Σ_k a_k·w_k`` over the last axis (``weights`` ``(6,)`` or per pixel ``(..., 6)``)."""
    return f32(np.sum(coeffs * weights, axis=-1, dtype=np.float32))


def ptm_color(coeffs: F32, rgb: F32 | None, weights: F32, intensity: float = 1.0) -> F32:
    """The colour mode's unclamped ``c``: lrgb ``rgb·L·I``, rgb ``Σ_k a_{c,k}·w_k·I``.

    Parameters
    ----------
    coeffs:
        ``(..., 6)`` luminance coefficients with ``rgb`` ``(..., 3)`` (lrgb), or ``(..., 3, 6)``
        per-channel coefficients with ``rgb`` ``None``.
    weights:
        ``(6,)`` basis weights of one light, or ``(..., 6)`` per pixel (:func:`ptm_basis`).
    intensity:
        ``lightIntensity``.
    """
    li = np.float32(intensity)
    if rgb is not None:
        return (rgb * (evaluate(coeffs, weights) * li)[..., None]).astype(np.float32)
    return (evaluate(coeffs, np.asarray(weights, np.float32)[..., None, :]) * li).astype(np.float32)


def diffuse_gain_coefficients(a: F32, n: F32, gain: float) -> F32:
    """Malzbender's diffuse gain: curvature × ``gain``, value and slope at the normal kept.

    Parameters
    ----------
    a:
        ``(H, W, 6)`` or ``(H, W, 3, 6)`` coefficients.
    n:
        ``(H, W, 3)`` normals (the shared, averaged normal for rgb).
    gain:
        ``g`` (``diffuseGain``).
    """
    nu, nv = n[..., 0], n[..., 1]
    if a.ndim == 4:
        nu, nv = nu[..., None], nv[..., None]
    g, h = np.float32(gain), np.float32(1.0 - gain)
    a0, a1, a2, a3, a4, a5 = (a[..., k] for k in range(6))
    b3 = h * (np.float32(2) * a0 * nu + a2 * nv) + a3
    b4 = h * (np.float32(2) * a1 * nv + a2 * nu) + a4
    b5 = h * (a0 * nu * nu + a1 * nv * nv + a2 * nu * nv) + (a3 - b3) * nu + (a4 - b4) * nv + a5
    out: F32 = np.stack([g * a0, g * a1, g * a2, b3, b4, b5], axis=-1).astype(np.float32)
    return out


def ptm_surface(layer: Mapping[str, Any], channels: Mapping[str, F32]) -> Surface:
    """Build the :class:`~.shading.Surface` of a PTM layer from its dequantised channels."""
    a = ptm_coefficients(layer, channels)
    n = ptm_normals(a)
    lrgb = a.ndim == 3
    rgb = (np.stack([channels[c] for c in "RGB"], axis=-1).astype(np.float32) if lrgb
           else np.zeros(0, np.float32))

    def relight(coeffs: F32, light: Light) -> F32:
        """Unclamped colour of coefficients ``coeffs`` (lrgb: luminance set × rgb)."""
        return ptm_color(coeffs, rgb if lrgb else None, ptm_basis(light.lu, light.lv),
                         light.intensity)

    def color(light: Light) -> F32:
        return relight(a, light)

    def luminance(light: Light) -> F32:
        return evaluate(a, ptm_basis(light.lu, light.lv))

    def specular(light: Light, p: Params) -> F32:
        s = np.power(clamp01(dot3(n, light.h)), np.float32(p["specExponent"]))[..., None]
        kd, ks, li = np.float32(p["specKd"]), np.float32(p["specKs"]), np.float32(light.intensity)
        if lrgb:
            return ((rgb * kd + ks * s) * (luminance(light) * li)[..., None]).astype(np.float32)
        c = color(light)
        return (c * kd + mean_rgb(c)[..., None] * ks * np.float32(2) * s).astype(np.float32)

    def diffuse_gain(light: Light, p: Params) -> F32:
        return relight(diffuse_gain_coefficients(a, n, p["diffuseGain"]), light)

    def unsharp_coefficients(filt: Any) -> Any:
        def mode(light: Light, p: Params) -> F32:
            if lrgb:
                lum = luminance(light)
                sharp = unsharp(lum, filt(lum), p["umGain"])
                return (rgb * (sharp * np.float32(light.intensity))[..., None]).astype(np.float32)
            c = color(light)
            return unsharp(c, filt(c), p["umGain"])
        return mode

    special: dict[str, Any] = {"specular": specular, "diffuseGain": diffuse_gain,
                               "unsharpCoefficients": unsharp_coefficients(f3)}
    if lrgb:
        special["achromatic"] = lambda light, p: grey(luminance(light)
                                                      * np.float32(light.intensity))
        special["unsharpLuminance"] = unsharp_coefficients(f5)
        albedo = rgb
    else:
        albedo = evaluate(a, ptm_basis(n[..., 0], n[..., 1])[..., None, :])
    return Surface(color=color, normal=n, albedo=albedo, special=special)
