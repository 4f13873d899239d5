"""Measurement mode in the reference (docs/rendering.md, "Measurement mode"): what the viewer
plots for the pixel under the cursor, from that pixel's dequantised channels.

- shape + material layers: the BRDF slice φd = 90° (Rusinkiewicz 1998) of Lambert + Ward,
  :func:`brdf_slice`;
- relightable layers (PTM, HSH, SH, RBF, bilinear): the colour over the whole light hemisphere,
  as a disk, :func:`reflectance_disk`;
- images (and shape + material layers without a normal map): the displayed colour,
  :func:`swatch`.

Each evaluates the renderer's own model functions (:func:`.svbrdf.ward_lobe`, the layer's
:func:`.modes.surface`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np
import numpy.typing as npt

from .modes import surface
from .shading import F32, f32, make_light
from .svbrdf import image_surface, svbrdf_material, svbrdf_surface, ward_lobe

#: Samples per axis of the plots the viewer shows.
SLICE_SIZE = 32
DISK_SIZE = 48


def slice_angles(n: int = SLICE_SIZE) -> F32:
    """The ``n`` sample angles of each slice axis: ``(i + ½)·(π/2)/n`` radians, ascending."""
    return f32((np.arange(n, dtype=np.float32) + np.float32(0.5)) * np.float32(math.pi / 2 / n))


def brdf_slice(kd: npt.ArrayLike, ks: npt.ArrayLike, alpha: float, n: int = SLICE_SIZE) -> F32:
    """The φd = 90° slice of Lambert + isotropic Ward, ``π·f(θh, θd)`` (E = π: kd shows as kd).

    In the normal's frame, with ``h`` at azimuth 0 and φd = 90°,
    ``l = (cosθd·sinθh, sinθd, cosθd·cosθh)``, ``v = (cosθd·sinθh, −sinθd, cosθd·cosθh)``, so
    ``n·l = n·v = cosθd·cosθh`` and ``n·h = cosθh``:
    ``π·f = kd + ks·exp(−tan²θh/α²)/(4α²·cosθd·cosθh)``. The slice of an isotropic BRDF does
    not depend on the normal.

    Parameters
    ----------
    kd, ks:
        ``(3,)`` linear reflectances (as the shader uses them).
    alpha:
        Ward roughness.
    n:
        Samples per axis (:func:`slice_angles`).

    Returns
    -------
    numpy.ndarray
        ``(n, n, 3)`` float32: row ``j`` is θd (top row θd ≈ 0), column ``i`` is θh.
    """
    t = slice_angles(n)
    th, td = np.meshgrid(t, t)  # th varies along a row, td down the columns
    cos_h, cos_d = np.cos(th).astype(np.float32), np.cos(td).astype(np.float32)
    lobe = ward_lobe(cos_h, np.float32(alpha)) / (cos_d * cos_h)
    return f32(f32(kd) + f32(ks) * lobe[..., None])


def disk_lights(size: int = DISK_SIZE) -> tuple[F32, F32, npt.NDArray[np.bool_]]:
    """The light ``(lu, lv)`` at the centre of each pixel of a ``size``² disk, and the inside mask.

    Orthographic, as the light widget: ``lu = 2(i + ½)/size − 1`` (right), ``lv = 1 −
    2(j + ½)/size`` (up); outside the unit circle the light is ``(0, 0)`` and the mask false.
    """
    c = (np.arange(size, dtype=np.float64) + 0.5) * 2 / size - 1
    lu, lv = np.meshgrid(c, -c)
    inside = lu * lu + lv * lv <= 1
    return (f32(np.where(inside, lu, 0)), f32(np.where(inside, lv, 0)), inside)


#: The layer types a measurement plots as a reflectance disk (the colour over the light hemisphere).
DISK_TYPES = frozenset({"ptm", "hsh", "sh", "rbf", "bilinear"})


def reflectance_disk(layer: Mapping[str, Any], coefficients: Mapping[str, float],
                     size: int = DISK_SIZE, intensity: float = 1.0) -> F32:
    """The colour mode's unclamped ``c`` of one relightable pixel for every light of a disk.

    The layer's own model (:func:`.modes.surface`: PTM, HSH, SH, RBF, bilinear) evaluated at each
    disk light, so the disk is by construction what the colour mode shows under that light.

    Parameters
    ----------
    layer:
        The layer's relight service block (a :data:`DISK_TYPES` type).
    coefficients:
        The pixel's dequantised channels by name (``L0…L5, R, G, B``; ``R0…B{K−1}``; ``P0…``).
    size:
        Disk side in pixels (:func:`disk_lights`).
    intensity:
        ``lightIntensity``.

    Returns
    -------
    numpy.ndarray
        ``(size, size, 3)`` float32, rows top-down; 0 outside the disk.
    """
    kind = layer.get("layerType")
    if kind not in DISK_TYPES:
        raise ValueError(f"a reflectance disk needs a {', '.join(sorted(DISK_TYPES))} layer, "
                         f"not {kind!r}")
    model = surface(layer, {k: np.full((1, 1), v, np.float32) for k, v in coefficients.items()})
    lu, lv, inside = disk_lights(size)
    out = np.zeros((size, size, 3), np.float32)
    for j, i in zip(*np.nonzero(inside), strict=True):
        out[j, i] = model.color(make_light(float(lu[j, i]), float(lv[j, i]), intensity))[0, 0]
    return out


def material_slice(layer: Mapping[str, Any], coefficients: Mapping[str, float],
                   n: int = SLICE_SIZE) -> F32:
    """:func:`brdf_slice` of a shape + material pixel's own kd, ks and α (with a normal map)."""
    channels = {k: np.full((1, 1), v, np.float32) for k, v in coefficients.items()}
    material = svbrdf_material(layer, channels)
    if material is None:
        raise ValueError("this shape + material layer has no normal map: no BRDF to plot")
    return brdf_slice(material.kd[0, 0], material.ks[0, 0], float(material.alpha[0, 0]), n)


def swatch(layer: Mapping[str, Any], coefficients: Mapping[str, float]) -> F32:
    """The displayed colour ``(3,)`` of an image pixel (or a shape + material one without shape)."""
    channels = {k: np.full((1, 1), v, np.float32) for k, v in coefficients.items()}
    make = svbrdf_surface if layer.get("layerType") == "svbrdf" else image_surface
    return f32(make(layer, channels).albedo[0, 0])
