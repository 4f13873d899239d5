"""Reference renderer, PCA layers (rbf, bilinear; mrgb, mycc) on synthetic bases built here."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import numpy.typing as npt
import pytest

from lanterna.tiler.formats.pca_model import PcaBasis, plane_channel_names
from lanterna.tiler.iiif.pyramid import vips_from_array, write_pyramid
from lanterna.tiler.render import (
    MODES,
    albedo,
    applicable_modes,
    f3,
    level_channels,
    normals,
    render,
    surface,
)
from lanterna.tiler.render.shading import make_light

F32 = npt.NDArray[np.float32]
F64 = npt.NDArray[np.float64]
LIGHTS = [(0.0, 0.0), (0.45, -0.3), (-0.6, 0.55)]
RENDERING_MD = Path(__file__).resolve().parents[3] / "docs" / "rendering.md"


def dome(count: int) -> F64:
    """``count`` unit lights on a Fibonacci spiral over the upper hemisphere (z ≥ 0.1)."""
    k = np.arange(count) + 0.5
    z = 0.1 + 0.9 * (1 - k / count)
    r = np.sqrt(1 - z * z)
    phi = k * math.pi * (3 - math.sqrt(5))
    return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1)


def octahedral_grid(res: int) -> F64:
    """The unit direction of each bilinear sample ``x + y·R`` (the inverse of Relight's map).

    ``u = 2x/(R − 1) − 1 = (lx + ly)/s``, ``v = 2y/(R − 1) − 1 = (ly − lx)/s``, so
    ``(lx, ly, lz) ∝ ((u − v)/2, (u + v)/2, 1 − max(|u|, |v|))``.
    """
    out = np.empty((res * res, 3))
    for y in range(res):
        for x in range(res):
            u, v = 2 * x / (res - 1) - 1, 2 * y / (res - 1) - 1
            d = np.array([(u - v) / 2, (u + v) / 2, 1 - max(abs(u), abs(v))])
            out[x + y * res] = d / np.linalg.norm(d)
    return out


def random_basis(layer_type: str, colorspace: str, nplanes: int, seed: int,
                 yccplanes: tuple[int, int, int] | None = None) -> PcaBasis:
    rng = np.random.default_rng(seed)
    samples = 60 if layer_type == "rbf" else 7 * 7
    raw = rng.integers(0, 256, (nplanes + 1) * samples * 3).astype(np.uint8)
    ranges = tuple(float(v) for v in rng.uniform(150, 600, nplanes))
    if layer_type == "rbf":
        return PcaBasis("rbf", colorspace, raw, ranges, tuple(dome(samples).ravel()), 0.3,
                        yccplanes=yccplanes)
    return PcaBasis("bilinear", colorspace, raw, ranges, resolution=7, yccplanes=yccplanes)


def block(basis: PcaBasis) -> dict[str, object]:
    return {"layerType": basis.layer_type, **basis.fields(), "planes": []}


def coefficients(h: int, w: int, nplanes: int, seed: int) -> dict[str, F32]:
    rng = np.random.default_rng(seed)
    return {f"P{q}": rng.uniform(-0.3, 0.3, (h, w)).astype(np.float32) for q in range(nplanes)}


def ycocg_to_rgb(y: F64) -> F64:
    """Relight's ``Color3::toRgb`` step by step: ``t = Y − Cg/2``, ``G = Cg + t``,
    ``B = t − Co/2``, ``R = B + Co``."""
    yy, co, cg = y[..., 0], y[..., 1], y[..., 2]
    t = yy - cg / 2
    b = t - co / 2
    return np.stack([b + co, cg + t, b], axis=-1)


@pytest.mark.parametrize("layer_type", ["rbf", "bilinear"])
def test_mycc_is_the_ycocg_of_the_mrgb_sums_of_each_channels_planes(layer_type: str) -> None:
    # 11 planes, yccplanes [5, 3, 3]: planes 0..8 go to Y, Co, Cg in turn, 9 and 10 to Y
    mycc = random_basis(layer_type, "mycc", 11, seed=1, yccplanes=(5, 3, 3))
    mrgb = PcaBasis(layer_type, "mrgb", mycc.basis, mycc.ranges, mycc.lights, mycc.sigma,
                    mycc.resolution)
    ch = coefficients(3, 4, 11, seed=2)
    of_channel = {0: [0, 3, 6, 9, 10], 1: [1, 4, 7], 2: [2, 5, 8]}
    for lu, lv in LIGHTS:
        light = make_light(lu, lv)
        got = surface(block(mycc), ch).color(light)
        ycc = np.empty(got.shape)
        for k, planes in of_channel.items():
            # the mrgb colour with only channel k's planes: its channel k is that YCC channel
            only = {name: (v if int(name[1:]) in planes else np.zeros_like(v))
                    for name, v in ch.items()}
            ycc[..., k] = surface(block(mrgb), only).color(light)[..., k]
        np.testing.assert_allclose(got, ycocg_to_rgb(ycc), atol=2e-6)


def lambertian(layer_type: str, res_or_count: int) -> tuple[PcaBasis, dict[str, F32], F64, F64]:
    """A Lambertian field ``c_k(l) = ρ_k·(n·l)`` written as a 9-plane mrgb PCA basis.

    Plane ``3k + j`` holds ``ρ_k·n_j``; its basis row samples ``l_j`` in channel ``k`` (0 in the
    others), quantised as Relight stores it: byte ``127 + round(127·l_j)``, range 127. The mean
    row is 0 (byte 0).
    """
    if layer_type == "rbf":
        dirs = dome(res_or_count)
    else:
        dirs = octahedral_grid(res_or_count)
    d = len(dirs)
    raw = np.full((10, d, 3), 127, np.uint8)  # value 0 in every channel…
    raw[0] = 0  # …and a zero mean
    for k in range(3):
        for j in range(3):
            raw[1 + 3 * k + j, :, k] = 127 + np.round(127 * dirs[:, j]).astype(np.int64)
    ranges = (127.0,) * 9
    if layer_type == "rbf":
        basis = PcaBasis("rbf", "mrgb", raw.ravel(), ranges, tuple(dirs.ravel()), 0.2)
    else:
        basis = PcaBasis("bilinear", "mrgb", raw.ravel(), ranges, resolution=res_or_count)
    rng = np.random.default_rng(5)
    h, w = 6, 7
    theta = rng.uniform(0, math.radians(40), (h, w))
    phi = rng.uniform(0, 2 * math.pi, (h, w))
    n = np.stack([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)], -1)
    rho = rng.uniform(0.2, 0.9, (h, w, 3))
    ch = {f"P{3 * k + j}": (rho[..., k] * n[..., j]).astype(np.float32)
          for k in range(3) for j in range(3)}
    return basis, ch, n, rho


@pytest.mark.parametrize(("layer_type", "size"), [("rbf", 400), ("bilinear", 17)])
def test_a_lambertian_basis_gives_back_its_normals_and_albedo(layer_type: str, size: int) -> None:
    """Normals within 1° and albedo within 3 %: the basis's 8-bit steps and its interpolation.

    (Measured: normals 0.04° (rbf, 400 lights, σ 0.2) and 0.53° (bilinear 17 × 17); albedo 1.9 %
    and 1.1 %, the RBF's weighted mean of nearby unit lights being slightly shorter than 1.)
    """
    basis, ch, n, rho = lambertian(layer_type, size)
    got_n = normals(block(basis), ch).astype(np.float64)
    angle = np.degrees(np.arccos(np.clip(np.sum(got_n * n, axis=-1), -1, 1)))
    assert angle.max() < 1.0, f"normal off by {angle.max():.2f}°"
    got_rho = albedo(block(basis), ch)
    np.testing.assert_allclose(got_rho, rho, rtol=0.03)
    # and the colour at a light is ρ·(n·l), within the same 3 %
    for lu, lv in LIGHTS:
        light = make_light(lu, lv)
        shade = rho * np.sum(n * light.direction, axis=-1)[..., None]
        got = surface(block(basis), ch).color(light)
        np.testing.assert_allclose(got, shade, rtol=0.03, atol=0.01)


@pytest.mark.parametrize("layer_type", ["rbf", "bilinear"])
@pytest.mark.parametrize("colorspace", ["mrgb", "mycc"])
def test_every_mode_of_hsh_renders_and_the_others_are_refused(layer_type: str,
                                                              colorspace: str) -> None:
    ycc = (4, 1, 1) if colorspace == "mycc" else None
    basis = random_basis(layer_type, colorspace, 6, seed=3, yccplanes=ycc)
    layer = block(basis)
    ch = coefficients(12, 10, 6, seed=4)
    assert applicable_modes(layer) == applicable_modes({"layerType": "hsh", "terms": 9})
    for mode in applicable_modes(layer):
        out = render(layer, ch, (0.3, -0.2), mode)
        assert out.shape == (12, 10, 3) and out.dtype == np.float32, mode
        assert 0.0 <= out.min() and out.max() <= 1.0, mode
    for mode in ("diffuseGain", "unsharpLuminance"):
        with pytest.raises(ValueError, match="does not apply"):
            render(layer, ch, (0.3, -0.2), mode)


def documented_modes(column: str) -> tuple[str, ...]:
    """The ✓ rows of one column of docs/rendering.md's "Modes and where they apply"."""
    section = RENDERING_MD.read_text().split("## Modes and where they apply")[1].split("\n## ")[0]
    rows = [[c.strip() for c in line.split("|")[1:-1]] for line in section.splitlines()
            if line.startswith("| ")]
    col = rows[0].index(column)
    return tuple(r[0].strip("`") for r in rows[1:] if r[col].startswith("✓"))


@pytest.mark.parametrize("layer_type", ["rbf", "bilinear"])
def test_the_modes_are_those_of_the_docs_table(layer_type: str) -> None:
    layer = block(random_basis(layer_type, "mrgb", 3, seed=12))
    assert applicable_modes(layer) == documented_modes(layer_type)
    assert set(documented_modes(layer_type)) <= set(MODES)


def test_colour_specular_and_unsharp_follow_the_doc() -> None:
    basis = random_basis("rbf", "mrgb", 5, seed=6)
    layer = block(basis)
    ch = coefficients(9, 11, 5, seed=7)
    r = np.stack([ch[f"P{q}"] for q in range(5)], axis=-1).astype(np.float64)
    lu, lv = 0.35, 0.25
    w = basis.weights(lu, lv)
    c = w[0] + r @ w[1:]
    got = render(layer, ch, (lu, lv), params={"lightIntensity": 0.8})
    np.testing.assert_allclose(got, np.clip(c * 0.8, 0, 1), atol=1e-5)
    n = normals(layer, ch).astype(np.float64)
    s = np.clip(n @ make_light(lu, lv).h, 0, 1) ** (60 / 5)
    spec = c * 0.3 + c.mean(axis=-1, keepdims=True) * 0.6 * 4 * s[..., None]
    got = render(layer, ch, (lu, lv), "specular",
                 {"specKd": 0.3, "specKs": 0.6, "specExponent": 60})
    np.testing.assert_allclose(got, np.clip(spec, 0, 1), atol=1e-5)
    sharp = c + 2.0 * (c - f3(c.astype(np.float32)))
    got = render(layer, ch, (lu, lv), "unsharpCoefficients", {"umGain": 2.0})
    np.testing.assert_allclose(got, np.clip(sharp, 0, 1), atol=1e-5)


def test_a_missing_coefficient_channel_is_named() -> None:
    basis = random_basis("bilinear", "mrgb", 4, seed=8)
    ch = coefficients(2, 2, 4, seed=9)
    del ch["P2"]
    with pytest.raises(ValueError, match="P2"):
        render(block(basis), ch, (0.0, 0.0))


def test_level_channels_reads_the_plane_groups_with_their_padding(tmp_path: Path) -> None:
    """5 planes in groups P0–P2 and P3, P4, X5 (scale 0): read back from IIIF tiles, rendered."""
    basis = random_basis("rbf", "mrgb", 5, seed=10)
    rng = np.random.default_rng(11)
    texels = [rng.integers(0, 256, (20, 30, 3)).astype(np.uint8) for _ in range(2)]
    scale, bias = 0.8, 0.5
    (tmp_path / "iiif").mkdir()
    planes = []
    for g, names in enumerate(plane_channel_names(5)):
        image_id = f"pca_p{g}"
        write_pyramid(vips_from_array(texels[g]), tmp_path / "iiif" / image_id,
                      f"http://example.org/iiif/{image_id}")
        planes.append({"service": {"id": f"http://example.org/iiif/{image_id}"},
                       "format": "png", "channels": names,
                       "scale": [0.0 if n.startswith("X") else scale for n in names],
                       "bias": [0.0 if n.startswith("X") else bias for n in names]})
    assert planes[1]["channels"] == ["P3", "P4", "X5"]
    layer = {**block(basis), "planes": planes}
    ch = level_channels(tmp_path, layer, factor=1)
    assert not ch["X5"].any()
    t = np.concatenate(texels, axis=-1).astype(np.float64) / 255
    direct = {f"P{q}": ((t[..., q] - bias) * scale).astype(np.float32) for q in range(5)}
    np.testing.assert_allclose(render(layer, ch, (0.2, 0.4)), render(layer, direct, (0.2, 0.4)),
                               atol=1e-6)
