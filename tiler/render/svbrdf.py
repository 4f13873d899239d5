"""Shape and material (``layerType: "svbrdf"``) and plain ``image`` layers in the reference.

Lambert + isotropic Ward (Ngan et al. 2005) with ``E = π``, so ``kd`` is the apparent albedo;
a layer without a normal map is a pure image (docs/rendering.md).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from .shading import (
    F32,
    Light,
    Params,
    Surface,
    clamp01,
    dot3,
    f32,
    grey,
    linear_to_srgb,
    mean_rgb,
    normalize,
    srgb_to_linear,
)

#: Default BRDF of a shape without material (linear).
DEFAULT_KD, DEFAULT_KS, DEFAULT_ALPHA = 0.7, 0.15, 0.25


def _group(channels: Mapping[str, F32], names: tuple[str, ...]) -> F32 | None:
    if names[0] not in channels:
        return None
    return np.stack([channels[c] for c in names], axis=-1).astype(np.float32)


def ward(n: F32, kd: F32, ks: F32, alpha: F32, light: Light) -> F32:
    """Linear radiance ``kd·cosi + ks·exp(−tan²θh/α²)·√(cosi/cosr)/(4α²)`` (unclamped).

    Parameters
    ----------
    n:
        ``(H, W, 3)`` unit normals.
    kd, ks:
        ``(H, W, 3)`` linear reflectances (or broadcastable).
    alpha:
        ``(H, W)`` Ward roughness (or broadcastable).
    light:
        The light (its intensity is not applied here).
    """
    cosi = np.maximum(np.float32(0), dot3(n, light.direction))
    cosr = np.maximum(n[..., 2], np.float32(1e-4))
    spec = ward_lobe(dot3(n, light.h), alpha) * np.sqrt(cosi / cosr)
    return f32(kd * cosi[..., None] + ks * spec[..., None])


def ward_lobe(nh: npt.ArrayLike, alpha: npt.ArrayLike) -> F32:
    """Ward's specular lobe ``exp(−tan²θh/α²)/(4α²)`` of ``nh = n·h`` (clamped to ``≥ 1e-4``).

    The BRDF is ``π·f = kd + ks·lobe/√(cosθi·cosθo)`` (E = π); :func:`ward` multiplies it by
    ``cosθi``, the BRDF slice (:mod:`.measure`) plots it.
    """
    c = np.maximum(f32(nh), np.float32(1e-4))
    tan2 = (np.float32(1) - c * c) / (c * c)
    a2 = f32(alpha) * f32(alpha)
    return f32(np.exp(-tan2 / a2) / (np.float32(4) * a2))


@dataclass(frozen=True)
class Material:
    """The linear Lambert + Ward parameters of a shape + material layer, per pixel.

    ``n`` ``(H, W, 3)`` unit normals, ``kd`` and ``ks`` ``(H, W, 3)`` linear (display values for
    ``inputColorSpace: "display"``), ``alpha`` ``(H, W)``; missing maps take the contract's
    defaults.
    """

    n: F32
    kd: F32
    ks: F32
    alpha: F32


def svbrdf_material(layer: Mapping[str, Any], channels: Mapping[str, F32]) -> Material | None:
    """The :class:`Material` of a shape + material layer, ``None`` without a normal map."""
    normal = _group(channels, ("NX", "NY", "NZ"))
    if normal is None:
        return None
    lo, hi = (float(v) for v in layer.get("glossLimits", (0.01, 0.5)))
    srgb_in = layer.get("inputColorSpace", "linear") == "srgb"
    stored_kd = _group(channels, ("KD_R", "KD_G", "KD_B"))

    def linear(x: F32) -> F32:
        return srgb_to_linear(x) if srgb_in else x

    n = normalize(normal)
    one = np.ones(n.shape, np.float32)
    if stored_kd is None:
        return Material(n, one * DEFAULT_KD, one * DEFAULT_KS, one[..., 0] * DEFAULT_ALPHA)
    stored_ks = _group(channels, ("KS_R", "KS_G", "KS_B"))
    ks = one * np.float32(0) if stored_ks is None else linear(stored_ks)
    gloss = channels.get("GLOSS")
    alpha = (one[..., 0] * np.float32((lo + hi) / 2) if gloss is None
             else f32(np.float32(lo) + gloss * np.float32(hi - lo)))
    return Material(n, linear(stored_kd), ks, alpha)


def svbrdf_surface(layer: Mapping[str, Any], channels: Mapping[str, F32]) -> Surface:
    """Build the :class:`~.shading.Surface` of a shape + material layer (any subset of maps)."""
    space = layer.get("inputColorSpace", "linear")
    srgb_in = space == "srgb"
    display = space == "display"  # maps and shading in display values: no decode, no encode

    def encode(x: F32) -> F32:
        return x if display else linear_to_srgb(x)

    material = svbrdf_material(layer, channels)
    if material is None:  # a pure image: kd as displayed, no light
        stored_kd = _group(channels, ("KD_R", "KD_G", "KD_B"))
        if stored_kd is None:
            shape = next(iter(channels.values())).shape
            disp = np.full(shape + (3,), linear_to_srgb(f32(DEFAULT_KD)), np.float32)
        else:
            disp = stored_kd if srgb_in or display else linear_to_srgb(stored_kd)
        return Surface(color=lambda light: disp, normal=None, albedo=disp)
    n, kd, ks, alpha = material.n, material.kd, material.ks, material.alpha

    def color(light: Light) -> F32:
        return encode(clamp01(ward(n, kd, ks, alpha, light) * np.float32(light.intensity)))

    def diffuse(light: Light, p: Params) -> F32:
        cosi = np.maximum(np.float32(0), dot3(n, light.direction))[..., None]
        return encode(clamp01(kd * cosi * np.float32(light.intensity)))

    def specular(light: Light, p: Params) -> F32:
        s = np.power(clamp01(dot3(n, light.h)), np.float32(p["specExponent"]))[..., None]
        c = color(light)
        kd_, ks_ = np.float32(p["specKd"]), np.float32(p["specKs"])
        return f32(c * kd_ + mean_rgb(c)[..., None] * ks_ * np.float32(2) * s)

    albedo = f32(np.broadcast_to(encode(kd), n.shape))
    return Surface(color=color, normal=n, albedo=albedo,
                   special={"diffuse": diffuse, "specular": specular})


def image_surface(layer: Mapping[str, Any], channels: Mapping[str, F32]) -> Surface:
    """Build the :class:`~.shading.Surface` of a plain image (``R,G,B`` or a grey ``Y``)."""
    rgb = _group(channels, ("R", "G", "B"))
    texel = rgb if rgb is not None else grey(channels["Y"])
    return Surface(color=lambda light: texel, normal=None, albedo=texel)
