"""Reference renderer, PTM layers: colour, normals-derived modes, diffuse gain, unsharp modes."""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt
import pytest

from lanterna.tiler.render import albedo, f3, f5, normals, render
from lanterna.tiler.render.ptm import diffuse_gain_coefficients, ptm_basis

F32 = npt.NDArray[np.float32]
LRGB = {"layerType": "ptm", "colorspace": "lrgb", "planes": []}
RGB = {"layerType": "ptm", "colorspace": "rgb", "planes": []}
LIGHTS = [(0.0, 0.0), (0.6, -0.3), (-0.2, 0.9)]


def bowl(h: int, w: int, seed: int) -> F32:
    """``(h, w, 6)`` coefficients of quadratics with an interior maximum, in display units."""
    rng = np.random.default_rng(seed)
    u0, v0 = rng.uniform(-0.4, 0.4, (2, h, w))
    a0, a1 = rng.uniform(-0.4, -0.2, (2, h, w))
    a2 = rng.uniform(-0.1, 0.1, (h, w))
    a3, a4 = -2 * a0 * u0 - a2 * v0, -2 * a1 * v0 - a2 * u0
    a5 = rng.uniform(0.5, 0.7, (h, w)) + a0 * u0 * u0 + a1 * v0 * v0 + a2 * u0 * v0
    return np.stack([a0, a1, a2, a3, a4, a5], axis=-1).astype(np.float32)


def lrgb_channels(coeffs: F32, rgb: F32) -> dict[str, F32]:
    out = {f"L{k}": coeffs[..., k] for k in range(6)}
    out.update({c: rgb[..., i] for i, c in enumerate("RGB")})
    return out


def rgb_channels(coeffs: F32) -> dict[str, F32]:
    """``coeffs`` ``(H, W, 3, 6)``."""
    return {f"{c}{k}": coeffs[..., i, k] for i, c in enumerate("RGB") for k in range(6)}


def test_a5_only_ptm_is_light_independent() -> None:
    a = np.zeros((4, 5, 6), np.float32)
    a[..., 5] = np.random.default_rng(0).uniform(0.2, 0.8, (4, 5))
    rgb = np.random.default_rng(1).uniform(0, 1, (4, 5, 3)).astype(np.float32)
    ch = lrgb_channels(a, rgb)
    first = render(LRGB, ch, LIGHTS[0])
    for light in LIGHTS[1:]:
        np.testing.assert_array_equal(render(LRGB, ch, light), first)
    np.testing.assert_allclose(first, rgb * a[..., 5:6], atol=1e-6)
    rgb_a = np.repeat(a[:, :, None, :], 3, axis=2)
    np.testing.assert_allclose(render(RGB, rgb_channels(rgb_a), (0.5, 0.5)),
                               np.repeat(a[..., 5:6], 3, axis=-1), atol=1e-6)


@pytest.mark.parametrize("light", LIGHTS)
def test_colour_is_the_polynomial(light: tuple[float, float]) -> None:
    a = bowl(3, 4, seed=2)
    rgb = np.full((3, 4, 3), 0.5, np.float32)
    lu, lv = light
    lum = a @ np.array([lu * lu, lv * lv, lu * lv, lu, lv, 1.0], np.float32)
    got = render(LRGB, lrgb_channels(a, rgb), light, params={"lightIntensity": 1.5})
    np.testing.assert_allclose(got, np.clip(0.5 * lum * 1.5, 0, 1)[..., None].repeat(3, -1),
                               atol=1e-6)
    ach = render(LRGB, lrgb_channels(a, rgb), light, "achromatic")
    np.testing.assert_allclose(ach[..., 1], np.clip(lum, 0, 1), atol=1e-6)


def test_albedo_of_rgb_ptm_is_the_maximum_and_diffuse_uses_it() -> None:
    a = np.stack([bowl(3, 3, 3), bowl(3, 3, 3), bowl(3, 3, 3)], axis=2)
    ch = rgb_channels(a)
    n = normals(RGB, ch)
    rho = albedo(RGB, ch)
    w = ptm_basis(n[..., 0], n[..., 1])
    np.testing.assert_allclose(rho[..., 0], np.sum(a[..., 0, :] * w, axis=-1), atol=1e-6)
    # the maximum: brighter than the polynomial anywhere else on a grid of lights
    for lu in np.linspace(-0.7, 0.7, 5):
        for lv in np.linspace(-0.7, 0.7, 5):
            other = np.sum(a[..., 0, :] * ptm_basis(lu, lv), axis=-1)
            assert (other <= rho[..., 0] + 1e-6).all()
    light = (0.3, -0.4)
    ldir = np.array([0.3, -0.4, math.sqrt(0.75)], np.float32)
    expected = rho * np.maximum(0, n @ ldir)[..., None] * 0.8
    got = render(RGB, ch, light, "diffuse", {"lightIntensity": 0.8})
    np.testing.assert_allclose(got, np.clip(expected, 0, 1), atol=1e-6)


def test_diffuse_gain_keeps_value_and_slope_at_the_normal_and_scales_curvature() -> None:
    a = bowl(2, 3, seed=4).astype(np.float64)
    n = np.random.default_rng(5).uniform(-0.5, 0.5, (2, 3, 3))
    g = 3.0
    b = diffuse_gain_coefficients(a.astype(np.float32), n.astype(np.float32), g).astype(
        np.float64)
    nu, nv = n[..., 0], n[..., 1]

    def value(c: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
        return (c[..., 0] * nu**2 + c[..., 1] * nv**2 + c[..., 2] * nu * nv + c[..., 3] * nu
                + c[..., 4] * nv + c[..., 5])

    def slope(c: npt.NDArray[np.float64]) -> tuple[npt.NDArray[np.float64], ...]:
        return (2 * c[..., 0] * nu + c[..., 2] * nv + c[..., 3],
                2 * c[..., 1] * nv + c[..., 2] * nu + c[..., 4])

    np.testing.assert_allclose(value(b), value(a), atol=1e-5)
    for got, want in zip(slope(b), slope(a), strict=True):
        np.testing.assert_allclose(got, want, atol=1e-5)
    np.testing.assert_allclose(b[..., :3], g * a[..., :3], atol=1e-6)
    ch = lrgb_channels(a.astype(np.float32), np.full((2, 3, 3), 0.9, np.float32))
    np.testing.assert_allclose(render(LRGB, ch, (0.2, 0.1), "diffuseGain", {"diffuseGain": 1}),
                               render(LRGB, ch, (0.2, 0.1)), atol=1e-6)


def test_specular_follows_rtiviewer() -> None:
    a = bowl(3, 3, seed=6)
    rgb = np.random.default_rng(7).uniform(0.2, 0.8, (3, 3, 3)).astype(np.float32)
    ch = lrgb_channels(a, rgb)
    n = normals(LRGB, ch)
    lu, lv = 0.4, 0.3
    ldir = np.array([lu, lv, math.sqrt(1 - lu * lu - lv * lv)])
    h = (ldir + [0, 0, 1]) / np.linalg.norm(ldir + [0, 0, 1])
    p = {"specKd": 0.3, "specKs": 0.9, "specExponent": 20}
    s = np.clip(n @ h, 0, 1) ** 20
    lum = a @ np.array([lu * lu, lv * lv, lu * lv, lu, lv, 1.0])
    expected = (rgb * 0.3 + 0.9 * s[..., None]) * lum[..., None]
    np.testing.assert_allclose(render(LRGB, ch, (lu, lv), "specular", p),
                               np.clip(expected, 0, 1), atol=1e-5)
    rgb_a = np.stack([a, a * 0.8, a * 0.6], axis=2)
    c = np.stack([rgb_a[..., i, :] @ np.array([lu * lu, lv * lv, lu * lv, lu, lv, 1.0])
                  for i in range(3)], axis=-1)
    n3 = normals(RGB, rgb_channels(rgb_a))
    s3 = np.clip(n3 @ h, 0, 1) ** 20
    expected = c * 0.3 + c.mean(axis=-1, keepdims=True) * 0.9 * 2 * s3[..., None]
    np.testing.assert_allclose(render(RGB, rgb_channels(rgb_a), (lu, lv), "specular", p),
                               np.clip(expected, 0, 1), atol=1e-5)


def test_unsharp_coefficient_modes_sharpen_the_relit_value() -> None:
    rng = np.random.default_rng(8)
    a = bowl(12, 14, seed=9)
    a[..., 5] += rng.uniform(-0.1, 0.1, (12, 14)).astype(np.float32)
    rgb = np.full((12, 14, 3), 0.7, np.float32)
    ch = lrgb_channels(a, rgb)
    light = (0.1, -0.2)
    lum = np.sum(a * ptm_basis(*light), axis=-1)
    for mode, filt in (("unsharpCoefficients", f3), ("unsharpLuminance", f5)):
        sharp = lum + 2.0 * (lum - filt(lum))
        np.testing.assert_allclose(render(LRGB, ch, light, mode, {"umGain": 2.0}),
                                   np.clip(0.7 * sharp, 0, 1)[..., None].repeat(3, -1),
                                   atol=1e-5)
    # a spatially constant field is not changed
    flat = lrgb_channels(np.broadcast_to(a[0, 0], a.shape).copy(), rgb)
    np.testing.assert_allclose(render(LRGB, flat, light, "unsharpLuminance", {"umGain": 5.0}),
                               render(LRGB, flat, light), atol=1e-6)
    with pytest.raises(ValueError, match="unsharpLuminance"):
        render(RGB, rgb_channels(np.stack([a] * 3, axis=2)), light, "unsharpLuminance")
