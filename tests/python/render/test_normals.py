"""Reference-renderer normals: PTM (Malzbender's maximum) and HSH (three-light estimate)."""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt
import pytest

from lanterna.tiler.formats.hsh_basis import hsh_weights
from lanterna.tiler.formats.ptm_model import Ptm
from lanterna.tiler.render import hsh_basis, hsh_normals, ptm_normals
from lanterna.tiler.render.hsh import NORMAL_LIGHTS


def quadratic(u0: float, v0: float, a0: float = -1.0, a1: float = -2.0, a2: float = 0.5,
              a5: float = 0.3) -> npt.NDArray[np.float64]:
    """PTM coefficients of ``a0 du² + a1 dv² + a2 du dv + a5`` with ``du = u − u0``."""
    a3 = -2 * a0 * u0 - a2 * v0
    a4 = -2 * a1 * v0 - a2 * u0
    c = a5 + a0 * u0 * u0 + a1 * v0 * v0 + a2 * u0 * v0
    return np.array([a0, a1, a2, a3, a4, c])


@pytest.mark.parametrize("u0, v0", [(0.0, 0.0), (0.3, -0.2), (-0.5, 0.6), (0.1, 0.9)])
def test_ptm_normal_is_the_maximum_of_the_quadratic(u0: float, v0: float) -> None:
    n = ptm_normals(quadratic(u0, v0)[None, None])[0, 0]
    expected = np.array([u0, v0, math.sqrt(1 - u0 * u0 - v0 * v0)])
    np.testing.assert_allclose(n, expected, atol=1e-5)


def test_ptm_maximum_outside_the_disk_is_projected_on_the_rim() -> None:
    n = ptm_normals(quadratic(1.2, 0.9)[None, None])[0, 0]
    np.testing.assert_allclose(n, [0.8, 0.6, 0.0], atol=1e-5)


@pytest.mark.parametrize("coeffs", [
    [1.0, -2.0, 0.0, 0.1, 0.1, 0.5],  # a0 > 0: a saddle or a minimum
    [-1.0, -1.0, 2.0, 0.1, 0.1, 0.5],  # d = 4a0a1 − a2² = 0
    [0.0] * 6,
])
def test_ptm_without_interior_maximum_faces_the_viewer(coeffs: list[float]) -> None:
    n = ptm_normals(np.array(coeffs, np.float32)[None, None])
    np.testing.assert_array_equal(n[0, 0], [0, 0, 1])


def test_ptm_rgb_normal_averages_the_channel_normals() -> None:
    sets = np.stack([quadratic(0.3, 0.0), quadratic(0.0, 0.3), quadratic(0.0, 0.0)])
    n = ptm_normals(sets[None, None])[0, 0]
    avg = np.array([0.3, 0.0, math.sqrt(0.91)]) + [0.0, 0.3, math.sqrt(0.91)] + [0, 0, 1]
    np.testing.assert_allclose(n, avg / np.linalg.norm(avg), atol=1e-5)
    # opposite channel normals that cancel in x, y still average to a valid normal
    assert ptm_normals(np.stack([quadratic(0.5, 0), quadratic(-0.5, 0),
                                 quadratic(0, 0)])[None, None]).shape == (1, 1, 3)


def test_ptm_normals_shape_is_checked() -> None:
    with pytest.raises(ValueError):
        ptm_normals(np.zeros((2, 2, 5)))


@pytest.mark.parametrize("lu, lv", [(0, 0), (0.3, -0.5), (0.99, 0.1), (-0.2, 0.1), (0, -0.7)])
@pytest.mark.parametrize("terms", [4, 9, 16])
def test_vectorised_hsh_basis_equals_hsh_weights(lu: float, lv: float, terms: int) -> None:
    np.testing.assert_allclose(hsh_basis(lu, lv, terms), hsh_weights(lu, lv, terms), atol=1e-5)


def random_normals(count: int, min_z: float, seed: int) -> npt.NDArray[np.float64]:
    rng = np.random.default_rng(seed)
    n = rng.normal(size=(count, 3))
    n[:, 2] = np.abs(n[:, 2]) + 1e-3
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    return n[n[:, 2] >= min_z]


@pytest.mark.parametrize("terms", [4, 9, 16])
def test_hsh_normal_recovers_a_field_that_is_lambertian_at_the_three_lights(terms: int) -> None:
    # minimum-norm coefficients whose relights under the three normal lights are exactly n·l_i
    weights = np.stack([hsh_weights(float(u), float(v), terms) for u, v, _ in NORMAL_LIGHTS])
    normals = random_normals(40, 0.2, seed=1)
    albedo = np.array([0.5, 0.3, 0.2])
    lobes = normals @ NORMAL_LIGHTS.T.astype(np.float64)  # (N, 3 lights), may be negative
    a = lobes @ np.linalg.pinv(weights.astype(np.float64)).T  # (N, K)
    coeffs = albedo[None, :, None] * a[:, None, :]
    np.testing.assert_allclose(hsh_normals(coeffs), normals, atol=2e-4)


@pytest.mark.parametrize("terms, max_deg, mean_deg", [(4, 7, 3), (9, 12, 5), (16, 10, 3)])
def test_hsh_normal_of_a_fitted_lambertian_lobe(terms: int, max_deg: float,
                                                mean_deg: float) -> None:
    rng = np.random.default_rng(0)
    phi, z = rng.uniform(0, 2 * np.pi, 400), rng.uniform(0.1, 1, 400)
    lights = np.stack([np.sqrt(1 - z * z) * np.cos(phi), np.sqrt(1 - z * z) * np.sin(phi), z], -1)
    basis = hsh_basis(lights[:, 0], lights[:, 1], terms).astype(np.float64)
    normals = random_normals(60, 0.6, seed=2)
    fit, *_ = np.linalg.lstsq(basis, np.maximum(0, lights @ normals.T), rcond=None)  # (K, N)
    coeffs = np.array([0.6, 0.3, 0.1])[None, :, None] * fit.T[:, None, :]
    got = hsh_normals(coeffs)
    angles = np.degrees(np.arccos(np.clip(np.sum(got * normals, axis=1), -1, 1)))
    assert angles.max() < max_deg and angles.mean() < mean_deg


def test_flat_hsh_field_faces_the_viewer() -> None:
    np.testing.assert_array_equal(hsh_normals(np.zeros((2, 3, 3, 9)))[1, 2], [0, 0, 1])
    with pytest.raises(ValueError):
        hsh_normals(np.zeros((2, 3, 5)))


# --- normals of a file's dequantised coefficients (the reference renderer's ptm_normals) -----


def _normal_ptm(coeff_rows: list[list[int]], scale: float = 0.1) -> Ptm:
    coeffs = np.array(coeff_rows, dtype=np.uint8)[None]  # (1, N, 6)
    rgb = np.full(coeffs.shape[:2] + (3,), 200, np.uint8)
    return Ptm("lrgb", coeffs, np.full(6, scale, np.float32), np.full(6, 128, np.int32), rgb)


def test_ptm_normals_match_the_maximum_of_the_quadratic() -> None:
    b = 128  # bias; a = (byte - 128) * 0.1
    ptm = _normal_ptm(
        [
            # -(lu-0.3)² - (lv+0.2)²: a0=a1=-1, a3=0.6, a4=-0.4 -> max at (0.3, -0.2)
            [b - 10, b - 10, b, b + 6, b - 4, b + 50],
            # with a cross term: a0=-2, a1=-1, a2=0.5, a3=0.4, a4=0.3
            [b - 20, b - 10, b + 5, b + 4, b + 3, b],
            # all zero -> (0, 0, 1)
            [b, b, b, b, b, b + 100],
            # convex (a0 > 0): no interior maximum -> (0, 0, 1)
            [b + 10, b + 10, b, b + 6, b, b],
            # max at (2, 0), outside the disk -> projected to the rim (1, 0, 0)
            [b - 10, b - 10, b, b + 40, b, b],
        ]
    )
    n = ptm_normals(ptm.dequantized())
    assert n.shape == (1, 5, 3) and n.dtype == np.float32
    np.testing.assert_allclose(np.linalg.norm(n, axis=-1), 1.0, atol=1e-6)

    def expected(lu: float, lv: float) -> list[float]:
        return [lu, lv, float(np.sqrt(1 - lu * lu - lv * lv))]

    np.testing.assert_allclose(n[0, 0], expected(0.3, -0.2), atol=1e-5)
    a0, a1, a2, a3, a4 = -2.0, -1.0, 0.5, 0.4, 0.3
    # grad = 0: [2a0 a2; a2 2a1] [lu lv]ᵀ = -[a3 a4]ᵀ
    lu, lv = np.linalg.solve([[2 * a0, a2], [a2, 2 * a1]], [-a3, -a4])
    np.testing.assert_allclose(n[0, 1], expected(lu, lv), atol=1e-5)
    np.testing.assert_allclose(n[0, 2], [0, 0, 1], atol=1e-6)
    np.testing.assert_allclose(n[0, 3], [0, 0, 1], atol=1e-6)
    np.testing.assert_allclose(n[0, 4], [1, 0, 0], atol=1e-6)


def test_ptm_normals_of_rgb_average_the_channels() -> None:
    lrgb = _normal_ptm([[118, 118, 128, 134, 124, 178]])
    red = lrgb.coefficients[0, 0]
    flat = np.array([128, 128, 128, 128, 128, 228], np.uint8)  # no interior max -> (0, 0, 1)
    coeffs = np.stack([red, red, flat])[None, None]  # (1, 1, 3, 6)
    rgb = Ptm("rgb", coeffs, lrgb.scale, lrgb.bias)
    n_red = ptm_normals(lrgb.dequantized())[0, 0]
    mean = (2 * n_red + np.array([0, 0, 1])) / 3
    n_rgb = ptm_normals(rgb.dequantized())[0, 0]
    np.testing.assert_allclose(n_rgb, mean / np.linalg.norm(mean), atol=1e-6)
