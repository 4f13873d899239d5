"""Shade the demo tablet under a dome of lights and fit its PTM.

:func:`render` shades a :class:`~lanterna.tiler.demo.tablet.DemoObject` (Lambert plus Blinn-Phong
on the inlay), :func:`demo_lights` is a hemisphere of light directions, and :func:`make_demo_ptm`
fits an LRGB PTM to the renders. Axes: x right, y up, z toward the camera.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from lanterna.tiler.fit.ptm import fit_ptm_lrgb
from lanterna.tiler.formats.ptm_model import Ptm

from .tablet import AMBIENT, DemoObject, make_demo_object

F32 = npt.NDArray[np.float32]


def render(obj: DemoObject, light: npt.ArrayLike) -> F32:
    """Shade the object for a distant light seen by an orthographic camera.

    ``albedo · (AMBIENT + (1 − AMBIENT)·max(0, n·l)) + specular · color · (n·h)^shininess``
    with ``h = normalize(l + (0, 0, 1))``; the specular term is faded out as ``n·l → 0``.
    No cast shadows.

    Parameters
    ----------
    obj : DemoObject
    light : array_like, shape (3,)
        Direction toward the light (x right, y up, z toward the camera); normalised here.

    Returns
    -------
    ndarray of float32, shape (H, W, 3)
        Display-referred values clipped to 0–1.

    Raises
    ------
    ValueError
        If ``light`` is not a finite, non-zero 3-vector.
    """
    lv = np.asarray(light, dtype=np.float32)
    if lv.shape != (3,) or not np.all(np.isfinite(lv)) or float(np.linalg.norm(lv)) < 1e-9:
        raise ValueError(f"light must be a finite non-zero 3-vector, got {lv!r}")
    lv = lv / np.linalg.norm(lv)
    ndotl = obj.normals @ lv
    lit = np.maximum(ndotl, 0.0)
    out = obj.albedo * (AMBIENT + (1.0 - AMBIENT) * lit)[..., None]
    half = lv + np.array([0.0, 0.0, 1.0], dtype=np.float32)
    half /= np.linalg.norm(half)
    ndoth = np.maximum(obj.normals @ half, 0.0)
    fade = np.clip(ndotl * 5.0, 0.0, 1.0)
    spec = obj.specular * fade * ndoth**obj.shininess
    out = out + spec[..., None] * obj.specular_color
    shaded: F32 = np.clip(out, 0.0, 1.0).astype(np.float32)
    return shaded


def demo_lights(n_lights: int = 48) -> npt.NDArray[np.float64]:
    """Return ``n_lights`` unit light directions on rings of a hemisphere dome (lz ≥ 0.2).

    Four rings at elevations 12°, 30°, 50° and 72° share the lights in proportion to
    their circumference; successive rings are rotated half a step.

    Parameters
    ----------
    n_lights : int
        At least 12 (every ring gets at least 3).

    Returns
    -------
    ndarray, shape (n_lights, 3)

    Raises
    ------
    ValueError
        If ``n_lights < 12``.
    """
    if n_lights < 12:
        raise ValueError(f"need at least 12 lights, got {n_lights}")
    elevations = np.radians([12.0, 30.0, 50.0, 72.0])
    weights = np.cos(elevations)
    counts = np.maximum(3, np.floor(n_lights * weights / weights.sum())).astype(int)
    counts[0] += n_lights - int(counts.sum())
    dirs = []
    for ring, (el, c) in enumerate(zip(elevations, counts, strict=True)):
        az = (np.arange(c) + 0.5 * (ring % 2)) * (2.0 * np.pi / c)
        dirs.append(
            np.stack(
                [np.cos(az) * np.cos(el), np.sin(az) * np.cos(el), np.full(c, np.sin(el))], axis=1
            )
        )
    return np.concatenate(dirs, axis=0)


def render_stack(obj: DemoObject, lights: npt.ArrayLike) -> npt.NDArray[np.uint8]:
    """Render the object under each light and return ``(N, H, W, 3)`` ``uint8`` images.

    Raises
    ------
    ValueError
        If ``lights`` is not ``(N, 3)``.
    """
    lv = np.asarray(lights, dtype=np.float64)
    if lv.ndim != 2 or lv.shape[1] != 3:
        raise ValueError(f"lights must have shape (N, 3), got {lv.shape}")
    h, w = obj.shape
    out = np.empty((lv.shape[0], h, w, 3), dtype=np.uint8)
    for i, light in enumerate(lv):
        out[i] = np.rint(render(obj, light) * 255.0).astype(np.uint8)
    return out


def make_demo_ptm(width: int = 1024, height: int = 768, n_lights: int = 48, seed: int = 0) -> Ptm:
    """Render the demo tablet under :func:`demo_lights` and fit an LRGB PTM to it.

    The renders are rounded to 8 bits (as camera images would be) before the fit.

    Parameters
    ----------
    width, height : int
        Image size (at least 64 × 64).
    n_lights : int
        Number of lights (at least 12).
    seed : int
        Seed of the object.

    Returns
    -------
    Ptm
    """
    obj = make_demo_object(width, height, seed)
    lights = demo_lights(n_lights)
    return fit_ptm_lrgb(render_stack(obj, lights), lights)
