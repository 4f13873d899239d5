"""Shared shading maths of docs/rendering.md: lights, colour transfer, luma, the post step.

Every function works in float32, like the plugin's shaders, so that the reference renderer and
the GPU round the same way up to a few ulps.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

F32 = npt.NDArray[np.float32]

#: Rec. 709 luma weights: ``luma(c) = 0.2126 r + 0.7152 g + 0.0722 b``.
LUMA = np.array([0.2126, 0.7152, 0.0722], np.float32)


@dataclass(frozen=True)
class Light:
    """A light for one render: the unit direction ``l``, the half vector ``h`` and the intensity.

    Attributes
    ----------
    lu, lv:
        Projection of the light on the image plane (x right, y up).
    direction:
        ``(3,)`` float32 unit vector ``(lu, lv, √(1 − lu² − lv²))``.
    h:
        ``(3,)`` float32 ``normalize(l + v)`` with the view ``v = (0, 0, 1)``.
    intensity:
        ``lightIntensity``: multiplies the shaded value before the first clamp.
    """

    lu: float
    lv: float
    direction: F32
    h: F32
    intensity: float


def make_light(lu: float, lv: float, intensity: float = 1.0) -> Light:
    """Return the :class:`Light` for the projected direction ``(lu, lv)``.

    Raises
    ------
    ValueError
        If ``(lu, lv)`` lies outside the unit disk (beyond rounding).
    """
    r2 = lu * lu + lv * lv
    if not math.isfinite(r2) or r2 > 1.0 + 1e-6:
        raise ValueError(f"light ({lu}, {lv}) is outside the unit disk")
    lz = math.sqrt(max(0.0, 1.0 - r2))
    l_vec = np.array([lu, lv, lz], np.float32)
    h = l_vec + np.array([0.0, 0.0, 1.0], np.float32)
    h = (h / np.linalg.norm(h)).astype(np.float32)
    return Light(float(lu), float(lv), l_vec, h, float(intensity))


def f32(x: npt.ArrayLike) -> F32:
    """``x`` as a float32 array (numpy reductions may return scalars)."""
    return np.asarray(x, np.float32)


def dot3(a: npt.ArrayLike, b: npt.ArrayLike) -> F32:
    """Per-pixel dot product of ``(..., 3)`` fields (or a field with a ``(3,)`` vector)."""
    return f32(np.sum(f32(a) * f32(b), axis=-1, dtype=np.float32))


def normalize(v: F32, fallback: tuple[float, float, float] | None = None,
              eps: float = 0.0) -> F32:
    """Normalise ``(..., 3)`` vectors; where the length is ``<= eps`` use ``fallback``.

    Without a fallback a zero vector stays zero (GLSL would give NaN; the test data avoid it).
    """
    v = np.asarray(v, np.float32)
    length = np.sqrt(dot3(v, v))[..., None]
    out = v / np.where(length > 0, length, np.float32(1)).astype(np.float32)
    if fallback is not None:
        out = np.where(length > eps, out, np.asarray(fallback, np.float32))
    result: F32 = out.astype(np.float32)
    return result


def clamp01(x: F32) -> F32:
    """``min(max(x, 0), 1)``."""
    out: F32 = np.clip(np.asarray(x, np.float32), np.float32(0), np.float32(1))
    return out


def luma(c: F32) -> F32:
    """``0.2126 r + 0.7152 g + 0.0722 b`` of an ``(..., 3)`` colour, shape ``(...)``."""
    return dot3(c, LUMA)


def mean_rgb(c: F32) -> F32:
    """``(r + g + b)/3`` of an ``(..., 3)`` colour, shape ``(...)``."""
    return f32(np.sum(f32(c), axis=-1, dtype=np.float32) / np.float32(3))


def grey(y: F32) -> F32:
    """Repeat an ``(H, W)`` value into an ``(H, W, 3)`` grey colour."""
    out: F32 = np.repeat(np.asarray(y, np.float32)[..., None], 3, axis=-1)
    return out


def linear_to_srgb(x: F32) -> F32:
    """sRGB encoding: ``12.92x`` if ``x ≤ 0.0031308``, else ``1.055x^(1/2.4) − 0.055``.

    The input is clamped to 0–1 first (the contract only ever encodes clamped values).
    """
    x = clamp01(x)
    hi = np.float32(1.055) * np.power(x, np.float32(1 / 2.4)) - np.float32(0.055)
    out: F32 = np.where(x <= np.float32(0.0031308), np.float32(12.92) * x, hi).astype(np.float32)
    return out


def srgb_to_linear(x: F32) -> F32:
    """sRGB decoding: ``x/12.92`` if ``x ≤ 0.04045``, else ``((x + 0.055)/1.055)^2.4``."""
    x = np.asarray(x, np.float32)
    hi = np.power((x + np.float32(0.055)) / np.float32(1.055), np.float32(2.4))
    out: F32 = np.where(x <= np.float32(0.04045), x / np.float32(12.92), hi).astype(np.float32)
    return out


def post(c: F32, gamma: float = 1.0, brightness: float = 0.0) -> F32:
    """The post step of every mode: ``clamp01(clamp01(c)^(1/gamma) + brightness)``."""
    if gamma <= 0:
        raise ValueError(f"gamma must be positive, got {gamma}")
    out = np.power(clamp01(c), np.float32(1.0 / gamma)) + np.float32(brightness)
    return clamp01(out.astype(np.float32))


#: Render parameters by name (docs/rendering.md, "Parameters").
Params = dict[str, float]


@dataclass(frozen=True)
class Surface:
    """What a layer type provides to the mode dispatcher (:func:`~.modes.render`).

    Attributes
    ----------
    color:
        ``color(light) -> (H, W, 3)``: the colour mode's ``c`` before the post step.
    normal:
        ``(H, W, 3)`` unit normals, or ``None`` for a layer without shape (image-like).
    albedo:
        ``(H, W, 3)`` display albedo ``ρ``.
    special:
        Type-specific modes ``name -> f(light, params) -> c`` overriding the generic ones.
    """

    color: Callable[[Light], F32]
    normal: F32 | None
    albedo: F32
    special: Mapping[str, Callable[[Light, Params], F32]] = field(default_factory=dict)
