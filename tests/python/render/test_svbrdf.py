"""Reference renderer, shape + material and image layers: Lambert + Ward, defaults, sRGB."""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt
import pytest

from lanterna.tiler.render import linear_to_srgb, render, srgb_to_linear
from lanterna.tiler.render.shading import make_light
from lanterna.tiler.render.svbrdf import ward

F32 = npt.NDArray[np.float32]


def block(*groups: list[str], colorspace: str = "linear",
          limits: tuple[float, float] = (0.01, 0.5)) -> dict[str, object]:
    return {"layerType": "svbrdf", "glossLimits": list(limits), "inputColorSpace": colorspace,
            "planes": [{"channels": g} for g in groups]}


N, KD, KS, GLOSS = ["NX", "NY", "NZ"], ["KD_R", "KD_G", "KD_B"], ["KS_R", "KS_G", "KS_B"], ["GLOSS"]


def channels(n: F32 | None = None, kd: F32 | None = None, ks: F32 | None = None,
             gloss: F32 | None = None) -> dict[str, F32]:
    out: dict[str, F32] = {}
    for names, data in ((N, n), (KD, kd), (KS, ks)):
        if data is not None:
            out.update({c: data[..., i].astype(np.float32) for i, c in enumerate(names)})
    if gloss is not None:
        out["GLOSS"] = gloss.astype(np.float32)
    return out


def unit_normals(h: int, w: int, seed: int) -> F32:
    rng = np.random.default_rng(seed)
    n = rng.normal(size=(h, w, 3))
    n[..., 2] = np.abs(n[..., 2]) + 0.8
    return (n / np.linalg.norm(n, axis=-1, keepdims=True)).astype(np.float32)


def test_srgb_round_trip_and_known_values() -> None:
    x = np.linspace(0, 1, 1001, dtype=np.float32)
    np.testing.assert_allclose(srgb_to_linear(linear_to_srgb(x)), x, atol=2e-6)
    np.testing.assert_allclose(linear_to_srgb(srgb_to_linear(x)), x, atol=2e-6)
    np.testing.assert_allclose(linear_to_srgb(np.array([0.0, 0.0031308, 0.5, 1.0])),
                               [0.0, 0.04045, 0.735357, 1.0], atol=1e-5)
    np.testing.assert_allclose(linear_to_srgb(np.array([-1.0, 2.0])), [0.0, 1.0], atol=1e-6)


@pytest.mark.parametrize("light", [(0.0, 0.0), (0.5, 0.2), (-0.3, -0.8)])
def test_kd_only_is_lambert(light: tuple[float, float]) -> None:
    n = unit_normals(4, 5, seed=1)
    kd = np.random.default_rng(2).uniform(0.1, 0.9, (4, 5, 3))
    ch = channels(n * 0.5 + 0.5, kd)  # stored (n + 1)/2 …
    ch = {k: (v - 0.5) * 2 if k in N else v for k, v in ch.items()}  # … and dequantised
    ldir = make_light(*light).direction
    lambert = kd * np.maximum(0, n @ ldir)[..., None] * 1.2
    got = render(block(N, KD), ch, light, params={"lightIntensity": 1.2})
    np.testing.assert_allclose(got, linear_to_srgb(lambert), atol=1e-5)
    np.testing.assert_allclose(render(block(N, KD), ch, light, "diffuse",
                                      {"lightIntensity": 1.2}), got, atol=1e-6)
    np.testing.assert_allclose(render(block(N, KD), ch, light, "albedo"), linear_to_srgb(kd),
                               atol=1e-6)


def test_ward_peaks_at_the_mirror_direction() -> None:
    n = np.array([[[0.3, -0.2, math.sqrt(1 - 0.13)]]], np.float32)
    kd, ks = np.zeros((1, 1, 3), np.float32), np.full((1, 1, 3), 0.05, np.float32)
    alpha = np.full((1, 1), 0.1, np.float32)
    mirror = 2 * n[0, 0, 2] * n[0, 0] - np.array([0, 0, 1])
    best, best_light = -1.0, (0.0, 0.0)
    for lu in np.linspace(-0.9, 0.9, 73):
        for lv in np.linspace(-0.9, 0.9, 73):
            if lu * lu + lv * lv < 1:
                v = float(ward(n, kd, ks, alpha, make_light(lu, lv))[0, 0, 0])
                if v > best:
                    best, best_light = v, (lu, lv)
    assert abs(best_light[0] - mirror[0]) < 0.05 and abs(best_light[1] - mirror[1]) < 0.05
    # at the mirror direction h = n: I = ks·√(cosi/cosr)/(4α²), cosi = cosr
    at = ward(n, kd, ks, alpha, make_light(float(mirror[0]), float(mirror[1])))
    np.testing.assert_allclose(at[0, 0], 0.05 / (4 * 0.01), rtol=1e-3)


def test_gloss_map_and_srgb_input() -> None:
    n = unit_normals(3, 3, seed=3)
    kd_lin = np.random.default_rng(4).uniform(0.05, 0.6, (3, 3, 3)).astype(np.float32)
    ks_lin = np.full((3, 3, 3), 0.2, np.float32)
    gloss = np.linspace(0, 1, 9, dtype=np.float32).reshape(3, 3)
    light = (0.2, 0.4)
    lin = render(block(N, KD, KS, GLOSS, limits=(0.05, 0.4)),
                 channels(n, kd_lin, ks_lin, gloss), light)
    alpha = 0.05 + gloss * 0.35
    expected = linear_to_srgb(ward(n, kd_lin, ks_lin, alpha, make_light(*light)))
    np.testing.assert_allclose(lin, expected, atol=1e-6)
    srgb = render(block(N, KD, KS, GLOSS, colorspace="srgb", limits=(0.05, 0.4)),
                  channels(n, linear_to_srgb(kd_lin), linear_to_srgb(ks_lin), gloss), light)
    np.testing.assert_allclose(srgb, lin, atol=2e-5)


def test_missing_maps_take_the_documented_defaults() -> None:
    n = unit_normals(2, 2, seed=5)
    light = (0.3, 0.3)
    geometry = render(block(N), channels(n), light)
    one = np.ones((2, 2, 3), np.float32)
    expected = ward(n, one * 0.7, one * 0.15, np.full((2, 2), 0.25, np.float32),
                    make_light(*light))
    np.testing.assert_allclose(geometry, linear_to_srgb(expected), atol=1e-6)
    kd = np.full((2, 2, 3), 0.4, np.float32)
    ks = np.full((2, 2, 3), 0.3, np.float32)
    no_gloss = render(block(N, KD, KS, limits=(0.1, 0.3)), channels(n, kd, ks), light)
    expected = ward(n, kd, ks, np.full((2, 2), 0.2, np.float32), make_light(*light))
    np.testing.assert_allclose(no_gloss, linear_to_srgb(expected), atol=1e-6)


def test_svbrdf_specular_mode() -> None:
    n = unit_normals(3, 4, seed=6)
    kd = np.full((3, 4, 3), 0.3, np.float32)
    ch = channels(n, kd)
    light = (-0.4, 0.1)
    c = render(block(N, KD), ch, light)
    s = np.clip(n @ make_light(*light).h, 0, 1) ** 30
    expected = c * 0.5 + c.mean(axis=-1, keepdims=True) * 0.6 * 2 * s[..., None]
    got = render(block(N, KD), ch, light, "specular",
                 {"specKd": 0.5, "specKs": 0.6, "specExponent": 30})
    np.testing.assert_allclose(got, np.clip(expected, 0, 1), atol=1e-6)


def test_without_shape_the_layer_is_an_unlit_image() -> None:
    kd = np.random.default_rng(7).uniform(0, 1, (3, 3, 3)).astype(np.float32)
    for light in [(0.0, 0.0), (0.7, 0.1)]:
        np.testing.assert_allclose(render(block(KD), channels(kd=kd), light,
                                          params={"lightIntensity": 3}),
                                   linear_to_srgb(kd), atol=1e-6)
        np.testing.assert_allclose(render(block(KD, colorspace="srgb"), channels(kd=kd), light),
                                   kd, atol=1e-6)
    np.testing.assert_allclose(render(block(KD), channels(kd=kd), mode="albedo"),
                               linear_to_srgb(kd), atol=1e-6)
    with pytest.raises(ValueError, match="normals"):
        render(block(KD), channels(kd=kd), mode="normals")


def test_image_layers_show_the_texels() -> None:
    rgb = np.random.default_rng(8).uniform(0, 1, (3, 4, 3)).astype(np.float32)
    img = {"layerType": "image", "planes": [{"channels": ["R", "G", "B"]}]}
    ch = {c: rgb[..., i] for i, c in enumerate("RGB")}
    np.testing.assert_allclose(render(img, ch, (0.5, 0.5), params={"lightIntensity": 2}), rgb,
                               atol=1e-7)
    grey = {"layerType": "image", "planes": [{"channels": ["Y"]}]}
    out = render(grey, {"Y": rgb[..., 0]}, mode="achromatic")
    np.testing.assert_allclose(out, np.repeat(rgb[..., :1], 3, axis=-1), atol=1e-6)


@pytest.mark.parametrize("light", [(0.0, 0.0), (0.4, -0.5)])
def test_display_space_shades_the_stored_values_as_they_are(light: tuple[float, float]) -> None:
    """``inputColorSpace: "display"`` (what lanterna fit writes): no decode, no final encode."""
    n = unit_normals(3, 4, seed=5)
    rng = np.random.default_rng(6)
    kd, ks = rng.uniform(0.1, 0.7, (3, 4, 3)), rng.uniform(0.0, 0.3, (3, 4, 3))
    gloss = rng.uniform(0, 1, (3, 4))
    ch = channels(n, kd, ks, gloss)
    alpha = 0.05 + gloss * 0.4
    radiance = ward(n, kd.astype(np.float32), ks.astype(np.float32), alpha.astype(np.float32),
                    make_light(*light))
    got = render(block(N, KD, KS, GLOSS, colorspace="display", limits=(0.05, 0.45)), ch, light)
    np.testing.assert_allclose(got, np.clip(radiance, 0, 1), atol=1e-5)
    linear = render(block(N, KD, KS, GLOSS, colorspace="linear", limits=(0.05, 0.45)), ch, light)
    np.testing.assert_allclose(linear, linear_to_srgb(np.clip(radiance, 0, 1)), atol=1e-5)
    assert float(np.abs(linear - got).max()) > 0.05  # the two spaces really differ
    albedo = render(block(N, KD, colorspace="display"), channels(n, kd), light, "albedo")
    np.testing.assert_allclose(albedo, kd, atol=1e-6)
    flat = render(block(KD, colorspace="display"), channels(kd=kd), light)
    np.testing.assert_allclose(flat, kd, atol=1e-6)
