"""Render modes: which apply to which layer, their parameters, and :func:`render` itself."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any

import numpy as np

from .filters import f5, unsharp
from .hsh import hsh_surface
from .pca import pca_surface
from .ptm import ptm_surface
from .sh import sh_surface
from .shading import (
    F32,
    Light,
    Params,
    Surface,
    clamp01,
    dot3,
    f32,
    grey,
    luma,
    make_light,
    normalize,
    post,
)
from .svbrdf import image_surface, svbrdf_surface

#: Every mode, in the order of docs/rendering.md's table.
MODES = ("color", "normals", "albedo", "diffuse", "achromatic", "specular", "diffuseGain",
         "unsharpNormals", "unsharpCoefficients", "unsharpLuminance", "unsharpImage")

#: Parameter name → (default, min, max).
PARAMETERS: dict[str, tuple[float, float, float]] = {
    "lightIntensity": (1.0, 0.0, 4.0),
    "gamma": (1.0, 0.2, 5.0),
    "brightness": (0.0, -1.0, 1.0),
    "specKd": (0.4, 0.0, 1.0),
    "specKs": (0.7, 0.0, 1.0),
    "specExponent": (75.0, 1.0, 150.0),
    "diffuseGain": (2.0, 1.0, 10.0),
    "umGain": (1.0, 0.01, 6.0),
    "umKd": (1.0, 0.5, 1.5),
    "umEnv": (0.5, 0.1, 2.0),
}

_IMAGE_MODES = ("color", "albedo", "achromatic", "unsharpImage")
_SHAPE_MODES = ("color", "normals", "albedo", "diffuse", "achromatic", "specular",
                "unsharpNormals", "unsharpImage")


def has_shape(layer: Mapping[str, Any]) -> bool:
    """Whether an svbrdf layer has a normal map (``NX, NY, NZ``)."""
    return any("NX" in p["channels"] for p in layer.get("planes", ()))


def applicable_modes(layer: Mapping[str, Any]) -> tuple[str, ...]:
    """Return the modes that apply to a layer (its service block), in :data:`MODES` order."""
    kind = layer.get("layerType")
    extra: tuple[str, ...]
    if kind == "ptm":
        extra = ("diffuseGain", "unsharpCoefficients")
        if layer.get("colorspace") == "lrgb":
            extra += ("unsharpLuminance",)
    elif kind in ("hsh", "sh", "rbf", "bilinear"):
        extra = ("unsharpCoefficients",)
    elif kind == "svbrdf" and has_shape(layer):
        extra = ()
    elif kind in ("svbrdf", "image"):
        return _IMAGE_MODES
    else:
        raise ValueError(f"unknown layerType {kind!r}")
    return tuple(m for m in MODES if m in _SHAPE_MODES + extra)


def resolve_params(params: Mapping[str, float] | None) -> Params:
    """Defaults overridden by ``params``; unknown names and out-of-range values are refused."""
    out = {name: spec[0] for name, spec in PARAMETERS.items()}
    for name, value in (params or {}).items():
        if name not in PARAMETERS:
            raise ValueError(f"unknown render parameter {name!r}")
        lo, hi = PARAMETERS[name][1:]
        if not lo <= float(value) <= hi:
            raise ValueError(f"{name} = {value} is outside {lo}–{hi}")
        out[name] = float(value)
    return out


_SURFACES: dict[str, Callable[[Mapping[str, Any], Mapping[str, F32]], Surface]] = {
    "ptm": ptm_surface, "hsh": hsh_surface, "sh": sh_surface, "rbf": pca_surface,
    "bilinear": pca_surface, "svbrdf": svbrdf_surface, "image": image_surface}


def surface(layer: Mapping[str, Any], channels: Mapping[str, F32]) -> Surface:
    """Return the per-pixel quantities (colour, normal, albedo, special modes) of a layer."""
    return _SURFACES[str(layer["layerType"])](layer, channels)


def normals(layer: Mapping[str, Any], channels: Mapping[str, F32]) -> F32:
    """The layer's ``(H, W, 3)`` unit normals; ``ValueError`` for a layer without shape."""
    n = surface(layer, channels).normal
    if n is None:
        raise ValueError(f"this {layer.get('layerType')} layer has no normals")
    return n


def albedo(layer: Mapping[str, Any], channels: Mapping[str, F32]) -> F32:
    """The layer's ``(H, W, 3)`` display albedo ``ρ``."""
    return surface(layer, channels).albedo


def shade(surf: Surface, mode: str, light: Light, p: Params) -> F32:
    """The mode's colour ``c`` before the post step (docs/rendering.md, "Modes")."""
    if mode in surf.special:
        return surf.special[mode](light, p)
    if mode == "color":
        return surf.color(light)
    if mode == "albedo":
        return surf.albedo
    if mode == "achromatic":
        return grey(luma(surf.color(light)))
    if mode == "unsharpImage":
        c0 = clamp01(surf.color(light))
        y = luma(c0)
        return f32(c0 + (unsharp(y, f5(y), p["umGain"]) - y)[..., None])
    n = surf.normal
    if n is None:
        raise ValueError(f"mode {mode!r} needs a normal")
    li = np.float32(light.intensity)
    if mode == "normals":
        return f32((n + np.float32(1)) * np.float32(0.5))
    if mode == "diffuse":
        return f32(surf.albedo * (np.maximum(np.float32(0), dot3(n, light.direction)) * li)[
            ..., None])
    if mode == "unsharpNormals":
        ne = normalize(unsharp(n, f5(n), p["umGain"]))
        kd, env = np.float32(p["umKd"]), np.float32(p["umEnv"])
        shading = (kd * clamp01(dot3(ne, light.direction)) + env) / (kd + env) * li
        return f32(surf.albedo * shading[..., None])
    raise ValueError(f"mode {mode!r} is not implemented for this layer")


def render(layer: Mapping[str, Any], channels: Mapping[str, F32],
           light: tuple[float, float] = (0.0, 0.0), mode: str = "color",
           params: Mapping[str, float] | None = None) -> F32:
    """Render a layer as the plugin does: display values in 0–1 before 8-bit rounding.

    Parameters
    ----------
    layer:
        The layer's relight service block (``layerType``, ``colorspace``, ``terms``, ``planes``,
        ``glossLimits``, ``inputColorSpace``…).
    channels:
        Dequantised channels by name, each ``(H, W)`` float32 (:func:`.levels.level_channels`).
        The array is the canvas of the screen-space filters (taps clamped at its edges, the
        layer covering all of it).
    light:
        ``(lu, lv)`` on the unit disk.
    mode:
        One of :func:`applicable_modes` for the layer.
    params:
        Render parameters (:data:`PARAMETERS`); missing ones take their defaults.

    Returns
    -------
    numpy.ndarray
        ``(H, W, 3)`` float32 display values in 0–1.

    Raises
    ------
    ValueError
        For a mode that does not apply to the layer, an unknown or out-of-range parameter, or a
        light outside the unit disk.
    """
    modes = applicable_modes(layer)
    if mode not in modes:
        raise ValueError(f"mode {mode!r} does not apply to this {layer.get('layerType')} layer; "
                         f"applicable: {', '.join(modes)}")
    p = resolve_params(params)
    surf = surface(layer, channels)
    c = shade(surf, mode, make_light(light[0], light[1], p["lightIntensity"]), p)
    if c.ndim != 3 or c.shape[2] != 3:
        raise AssertionError(f"mode {mode} produced {c.shape}")
    return post(c, p["gamma"], p["brightness"])
