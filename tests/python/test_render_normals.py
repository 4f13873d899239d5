"""Reference-renderer normals: PTM (Malzbender's maximum) and HSH (three-light estimate)."""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt
import pytest

from lanterna.tiler.formats.hsh_basis import hsh_weights
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
