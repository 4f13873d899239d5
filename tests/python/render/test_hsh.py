"""Reference renderer, HSH layers: colour, albedo along the normal, specular, unsharp."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
import pytest

from lanterna.tiler.formats.hsh_basis import hsh_weights
from lanterna.tiler.render import albedo, f3, hsh_normals, normals, render
from lanterna.tiler.render.shading import make_light

F32 = npt.NDArray[np.float32]


def field(h: int, w: int, terms: int, seed: int) -> F32:
    """``(h, w, 3, K)`` coefficients: a bright constant term plus small random higher terms."""
    rng = np.random.default_rng(seed)
    a = rng.uniform(-0.1, 0.1, (h, w, 3, terms)).astype(np.float32)
    a[..., 0] = rng.uniform(0.8, 1.2, (h, w, 3))
    a[..., 2] += 0.3  # brighter towards the zenith
    return a


def block(terms: int) -> dict[str, object]:
    return {"layerType": "hsh", "terms": terms, "planes": []}


def chans(a: F32) -> dict[str, F32]:
    return {f"{c}{k}": a[..., i, k] for i, c in enumerate("RGB") for k in range(a.shape[-1])}


@pytest.mark.parametrize("terms", [4, 9, 16])
def test_colour_is_the_hsh_sum(terms: int) -> None:
    a = field(3, 4, terms, seed=terms)
    for light in [(0.0, 0.0), (0.5, -0.5), (-0.1, 0.95)]:
        expected = a @ hsh_weights(*light, terms) * 0.9
        got = render(block(terms), chans(a), light, params={"lightIntensity": 0.9})
        np.testing.assert_allclose(got, np.clip(expected, 0, 1), atol=1e-6)


def test_normals_and_albedo_are_those_of_the_doc() -> None:
    a = field(4, 4, 9, seed=1)
    n = normals(block(9), chans(a))
    np.testing.assert_allclose(n, hsh_normals(a), atol=1e-7)
    rho = albedo(block(9), chans(a))
    for y, x in [(0, 0), (2, 3)]:
        lit = a[y, x] @ hsh_weights(float(n[y, x, 0]), float(n[y, x, 1]), 9)
        np.testing.assert_allclose(rho[y, x], lit, atol=1e-5)


def test_hsh_specular_uses_a_fifth_of_the_exponent_and_four_times_the_mean() -> None:
    a = field(3, 3, 16, seed=2)
    light = (0.3, 0.2)
    c = a @ hsh_weights(*light, 16)
    n = hsh_normals(a)
    s = np.clip(n @ make_light(*light).h, 0, 1) ** (50 / 5)
    expected = c * 0.2 + c.mean(axis=-1, keepdims=True) * 0.5 * 4 * s[..., None]
    got = render(block(16), chans(a), light, "specular",
                 {"specKd": 0.2, "specKs": 0.5, "specExponent": 50})
    np.testing.assert_allclose(got, np.clip(expected, 0, 1), atol=1e-5)


def test_hsh_unsharp_coefficients_sharpen_the_relit_colour() -> None:
    a = field(10, 12, 4, seed=3) * 0.5
    light = (-0.3, 0.4)
    c = a @ hsh_weights(*light, 4)
    expected = c + 1.5 * (c - f3(c))
    got = render(block(4), chans(a), light, "unsharpCoefficients", {"umGain": 1.5})
    np.testing.assert_allclose(got, np.clip(expected, 0, 1), atol=1e-5)
    with pytest.raises(ValueError):
        render(block(4), chans(a), light, "diffuseGain")
