"""Measurement mode in the reference: the BRDF slice, the hemisphere disk and the swatch."""

from __future__ import annotations

import math

import numpy as np
import pytest

from lanterna.tiler.formats.pca_model import PcaBasis
from lanterna.tiler.render import surface
from lanterna.tiler.render.measure import (
    brdf_slice,
    disk_lights,
    material_slice,
    reflectance_disk,
    slice_angles,
    swatch,
)
from lanterna.tiler.render.shading import make_light, srgb_to_linear
from lanterna.tiler.render.svbrdf import ward


def _rotation_to_z(v: np.ndarray) -> np.ndarray:
    """The rotation matrix taking the unit vector ``v`` to ``(0, 0, 1)`` (Rodrigues)."""
    z = np.array([0.0, 0.0, 1.0])
    axis = np.cross(v, z)
    s, c = np.linalg.norm(axis), float(v @ z)
    if s < 1e-12:
        return np.eye(3)
    k = axis / s
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    out: np.ndarray = np.eye(3) + s * kx + (1 - c) * (kx @ kx)
    return out


def test_slice_times_cos_theta_i_is_the_renderers_ward_for_that_geometry() -> None:
    kd, ks, alpha, n = np.array([0.5, 0.3, 0.2]), np.array([0.3, 0.2, 0.4]), 0.2, 8
    s = brdf_slice(kd, ks, alpha, n)
    t = slice_angles(n)
    for i, j in ((0, 0), (3, 1), (1, 3), (6, 2)):  # θd < 45°: the light stays above the image
        th, td = float(t[i]), float(t[j])
        l_loc = np.array([math.cos(td) * math.sin(th), math.sin(td), math.cos(td) * math.cos(th)])
        v_loc = np.array([math.cos(td) * math.sin(th), -math.sin(td), math.cos(td) * math.cos(th)])
        r = _rotation_to_z(v_loc)
        l_w, n_w = r @ l_loc, r @ np.array([0.0, 0.0, 1.0])
        light = make_light(float(l_w[0]), float(l_w[1]))
        radiance = ward(n_w[None, None].astype(np.float32), kd.astype(np.float32),
                        ks.astype(np.float32), np.float32(alpha), light)[0, 0]
        np.testing.assert_allclose(s[j, i] * float(l_w @ n_w), radiance, rtol=2e-5)


def test_slice_without_specular_is_kd_and_the_peak_is_at_small_theta_h() -> None:
    flat = brdf_slice([0.6, 0.5, 0.4], [0, 0, 0], 0.3, 16)
    np.testing.assert_allclose(flat, np.broadcast_to([0.6, 0.5, 0.4], flat.shape), rtol=1e-6)
    glossy = brdf_slice([0.1, 0.1, 0.1], [0.5, 0.5, 0.5], 0.1, 16)[..., 0]
    assert (np.argmax(glossy, axis=1) == 0).all()
    assert (np.diff(glossy[:, 0]) > 0).all()  # 1/cos θd


def test_material_slice_decodes_srgb_maps_and_gloss() -> None:
    layer = {"layerType": "svbrdf", "glossLimits": [0.02, 0.42], "inputColorSpace": "srgb",
             "planes": [{"channels": c} for c in (["NX", "NY", "NZ"], ["KD_R", "KD_G", "KD_B"],
                                                  ["KS_R", "KS_G", "KS_B"], ["GLOSS"])]}
    values = {"NX": 0.1, "NY": 0.0, "NZ": 0.9, "KD_R": 0.5, "KD_G": 0.4, "KD_B": 0.3,
              "KS_R": 0.2, "KS_G": 0.2, "KS_B": 0.6, "GLOSS": 0.5}
    kd = srgb_to_linear(np.array([0.5, 0.4, 0.3], np.float32))
    ks = srgb_to_linear(np.array([0.2, 0.2, 0.6], np.float32))
    np.testing.assert_allclose(material_slice(layer, values, 8), brdf_slice(kd, ks, 0.22, 8),
                               rtol=1e-6)
    with pytest.raises(ValueError, match="no normal map"):
        material_slice(layer, {k: v for k, v in values.items() if not k.startswith("N")})


def test_disk_lights_are_orthographic_and_the_disk_is_the_colour_mode_there() -> None:
    lu, lv, inside = disk_lights(5)
    assert (lu[2, 2], lv[2, 2], lu[2, 4], lv[0, 2]) == (0, 0, pytest.approx(0.8),
                                                        pytest.approx(0.8))
    assert not inside[0, 0] and inside.sum() == 21
    hsh = {"layerType": "hsh", "terms": 9,
           "planes": [{"channels": [f"R{k}", f"G{k}", f"B{k}"]} for k in range(9)]}
    rng = np.random.default_rng(3)
    values = {f"{c}{k}": float(rng.normal()) for k in range(9) for c in "RGB"}
    disk = reflectance_disk(hsh, values, 5, intensity=1.5)
    one = surface(hsh, {k: np.full((1, 1), v, np.float32) for k, v in values.items()})
    for j, i in ((2, 2), (1, 3), (4, 1)):
        want = one.color(make_light(float(lu[j, i]), float(lv[j, i]), 1.5))[0, 0]
        np.testing.assert_allclose(disk[j, i], want, rtol=1e-6, atol=1e-7)
    assert (disk[~inside] == 0).all()


def test_ptm_disk_and_swatch() -> None:
    lrgb = {"layerType": "ptm", "colorspace": "lrgb", "planes": []}
    values = {"L0": -0.3, "L1": -0.2, "L2": 0.1, "L3": 0.2, "L4": 0.0, "L5": 0.7,
              "R": 0.9, "G": 0.5, "B": 0.1}
    disk = reflectance_disk(lrgb, values, 3)
    lum = -0.3 * 0 + 0.7  # the centre pixel: overhead light
    np.testing.assert_allclose(disk[1, 1], np.array([0.9, 0.5, 0.1]) * lum, rtol=1e-6)
    image = {"layerType": "image", "planes": [{"channels": ["Y"]}]}
    np.testing.assert_array_equal(swatch(image, {"Y": 0.25}), [0.25, 0.25, 0.25])
    with pytest.raises(ValueError, match="needs a bilinear, hsh, ptm, rbf, sh layer, not 'image'"):
        reflectance_disk(image, {"Y": 0.25})


def test_sh_disk_is_relights_sh_formula() -> None:
    """An sh pixel's disk is ``c = Σ_k a_{c,k}·Y_k(l)``, Y Relight's real SH (stated here)."""
    sh = {"layerType": "sh", "terms": 9,
          "planes": [{"channels": [f"R{k}", f"G{k}", f"B{k}"]} for k in range(9)]}
    rng = np.random.default_rng(5)
    values = {f"{c}{k}": float(rng.normal()) for k in range(9) for c in "RGB"}
    disk = reflectance_disk(sh, values, 7)
    lu, lv, inside = disk_lights(7)
    for j, i in ((3, 3), (1, 4), (5, 2)):
        x, y = float(lu[j, i]), float(lv[j, i])
        z = math.sqrt(max(0.0, 1 - x * x - y * y))
        basis = [0.282095, 0.488603 * y, 0.488603 * z, 0.488603 * x, 1.092548 * x * y,
                 1.092548 * y * z, 0.315392 * (3 * z * z - 1), 1.092548 * x * z,
                 0.546274 * (x * x - y * y)]
        want = [sum(values[f"{c}{k}"] * basis[k] for k in range(9)) for c in "RGB"]
        np.testing.assert_allclose(disk[j, i], want, rtol=1e-5, atol=1e-6)
    assert (disk[~inside] == 0).all()


@pytest.mark.parametrize("layer_type", ["rbf", "bilinear"])
def test_pca_disk_is_the_colour_mode_at_each_light(layer_type: str) -> None:
    rng = np.random.default_rng(9)
    nplanes = 3
    raw = rng.integers(0, 256, (nplanes + 1) * (8 if layer_type == "rbf" else 25) * 3)
    if layer_type == "rbf":
        z = np.linspace(0.3, 1.0, 8)
        phi = np.arange(8) * 2.4
        r = np.sqrt(1 - z * z)
        lights = np.stack([r * np.cos(phi), r * np.sin(phi), z], 1)
        basis = PcaBasis("rbf", "mrgb", raw.astype(np.uint8), (300.0, 200.0, 150.0),
                         tuple(lights.ravel()), 0.4)
    else:
        basis = PcaBasis("bilinear", "mrgb", raw.astype(np.uint8), (300.0, 200.0, 150.0),
                         resolution=5)
    layer = {"layerType": layer_type, **basis.fields(), "planes": []}
    values = {f"P{q}": float(v) for q, v in enumerate(rng.uniform(-0.3, 0.3, nplanes))}
    disk = reflectance_disk(layer, values, 5, intensity=0.75)
    lu, lv, inside = disk_lights(5)
    one = surface(layer, {k: np.full((1, 1), v, np.float32) for k, v in values.items()})
    for j, i in ((2, 2), (1, 3), (3, 0)):
        want = one.color(make_light(float(lu[j, i]), float(lv[j, i]), 0.75))[0, 0]
        np.testing.assert_allclose(disk[j, i], want, rtol=1e-6, atol=1e-6)
    assert np.ptp(disk[inside], axis=0).max() > 0  # the colour changes with the light
    assert (disk[~inside] == 0).all()
