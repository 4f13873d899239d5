"""Reference renderer, sh layers (Relight's plain spherical harmonics): basis, colour, shape."""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt
import pytest

from lanterna.tiler.formats.sh_model import sh_basis, sh_weights
from lanterna.tiler.render import albedo, applicable_modes, normals, render
from tests.python.render.test_pca import documented_modes

F32 = npt.NDArray[np.float32]


def textbook_sh(x: float, y: float, z: float) -> list[float]:
    """The real spherical harmonics of bands 0–2 (no Condon–Shortley phase) with exact constants,
    in Relight's order ``Y00, Y1−1, Y10, Y11, Y2−2, Y2−1, Y20, Y21, Y22`` (y, z, x for band 1)."""
    pi = math.pi
    return [0.5 / math.sqrt(pi), math.sqrt(3 / (4 * pi)) * y, math.sqrt(3 / (4 * pi)) * z,
            math.sqrt(3 / (4 * pi)) * x, 0.5 * math.sqrt(15 / pi) * x * y,
            0.5 * math.sqrt(15 / pi) * y * z, 0.25 * math.sqrt(5 / pi) * (3 * z * z - 1),
            0.5 * math.sqrt(15 / pi) * x * z, 0.25 * math.sqrt(15 / pi) * (x * x - y * y)]


@pytest.mark.parametrize("light", [(0.0, 0.0), (0.6, 0.1), (-0.5, 0.4), (0.2, -0.95)])
def test_relights_constants_are_the_textbook_harmonics_rounded(light: tuple[float, float]
                                                               ) -> None:
    lu, lv = light
    lz = math.sqrt(1 - lu * lu - lv * lv)
    np.testing.assert_allclose(sh_weights(lu, lv, 9), textbook_sh(lu, lv, lz), atol=2e-6)
    np.testing.assert_array_equal(sh_weights(lu, lv, 4), sh_weights(lu, lv, 9)[:4])


def test_the_basis_over_arrays_is_the_basis_of_each_light() -> None:
    lu = np.array([[0.0, 0.3], [-0.7, 0.1]], np.float32)
    lv = np.array([[0.0, -0.2], [0.5, 0.9]], np.float32)
    grid = sh_basis(lu, lv, 9)
    assert grid.shape == (2, 2, 9) and grid.dtype == np.float32
    for i in range(2):
        for j in range(2):
            np.testing.assert_allclose(grid[i, j], sh_weights(float(lu[i, j]), float(lv[i, j]), 9),
                                       atol=1e-7)
    with pytest.raises(ValueError, match="4 or 9 terms"):
        sh_basis(0.0, 0.0, 16)


def lambertian(n: F32, rho: F32, terms: int) -> F32:
    """``(H, W, 3, K)`` coefficients of ``c(l) = ρ·(l·n)``: ``l·n = (n_y·Y1 + n_z·Y2 + n_x·Y3)/C1``
    (band 1 only), so the field is exact in 4 or 9 terms."""
    a = np.zeros(n.shape[:2] + (3, terms), np.float32)
    c1 = 0.488603
    for k, axis in ((1, 1), (2, 2), (3, 0)):
        a[..., k] = rho * n[..., axis, None] / c1
    return a


def chans(a: F32) -> dict[str, F32]:
    return {f"{c}{k}": a[..., i, k] for i, c in enumerate("RGB") for k in range(a.shape[-1])}


def unit_normals(h: int, w: int, seed: int) -> F32:
    rng = np.random.default_rng(seed)
    n = rng.normal(0, 0.4, (h, w, 3)).astype(np.float32)
    n[..., 2] = 1.0
    out: F32 = (n / np.linalg.norm(n, axis=-1, keepdims=True)).astype(np.float32)
    return out


@pytest.mark.parametrize("terms", [4, 9])
def test_a_lambertian_field_gives_back_its_normals_albedo_and_shading(terms: int) -> None:
    n = unit_normals(3, 5, seed=terms)
    rho = np.random.default_rng(1).uniform(0.2, 0.9, (3, 5, 3)).astype(np.float32)
    a = lambertian(n, rho, terms)
    block = {"layerType": "sh", "terms": terms, "planes": []}
    np.testing.assert_allclose(normals(block, chans(a)), n, atol=1e-5)
    np.testing.assert_allclose(albedo(block, chans(a)), rho, atol=1e-5)
    for lu, lv in [(0.0, 0.0), (0.5, -0.3), (-0.4, 0.6)]:
        lz = math.sqrt(1 - lu * lu - lv * lv)
        shade = np.maximum(n @ np.array([lu, lv, lz], np.float32), 0)[..., None]
        got = render(block, chans(a), (lu, lv), params={"lightIntensity": 0.8})
        np.testing.assert_allclose(got, np.clip(rho * shade * 0.8, 0, 1), atol=1e-5)


def test_sh_has_hsh_s_modes_as_the_docs_table_says() -> None:
    assert applicable_modes({"layerType": "sh"}) == applicable_modes({"layerType": "hsh"})
    assert applicable_modes({"layerType": "sh"}) == documented_modes("sh")
