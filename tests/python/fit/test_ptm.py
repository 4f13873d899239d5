"""The LRGB PTM fitter (``fit_ptm_lrgb``) on exact quadratic data: recovery, quantisation."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
import pytest

from lanterna.tiler.demo.dome import demo_lights
from lanterna.tiler.fit.ptm import (
    fit_ptm_lrgb,
    ptm_design_matrix,
    quantize_coefficients,
)


def _quadratic_case(
    colour: tuple[float, float, float],
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """Return (images, lights, a): luminance exactly ``B·a`` per pixel, peak ≤ 1."""
    rng = np.random.default_rng(7)
    lights = demo_lights(24)
    basis = ptm_design_matrix(lights)
    a = rng.uniform(-0.15, 0.15, size=(9, 11, 6))
    a[..., 5] = rng.uniform(0.45, 0.7, size=(9, 11))
    lum = np.einsum("nk,hwk->nhw", basis, a)
    assert lum.min() > 0.0 and lum.max() <= 1.0
    images = lum[..., None] * np.asarray(colour)
    return images, lights, a


@pytest.mark.parametrize("colour", [(1.0, 1.0, 1.0), (0.9, 0.55, 0.2)])
def test_fit_recovers_exact_quadratic(colour: tuple[float, float, float]) -> None:
    images, lights, a = _quadratic_case(colour)
    assert images.max() <= 1.0
    ptm = fit_ptm_lrgb(images, lights, band_rows=4)
    peak = np.einsum("nk,hwk->nhw", ptm_design_matrix(lights), a).max(axis=0)
    expected = 255.0 * a / peak[..., None]  # ptmfit: luminance normalised by its peak
    err = np.abs(ptm.dequantized() - expected / 255.0)
    assert np.all(err <= (ptm.scale / 2.0 + 1e-3) / 255.0)
    rgb = 255.0 * peak[..., None] * np.asarray(colour)  # Σ c·Yn / Σ Yn² = colour · peak
    assert ptm.rgb is not None
    assert np.all(np.abs(ptm.rgb.astype(np.float64) - rgb) <= 0.5 + 1e-3)
    # and the relit image reproduces the inputs
    for i, (lx, ly, _) in enumerate(lights):
        assert np.abs(ptm.relight(lx, ly) - images[i]).max() < 2.5 / 255.0


def test_fit_accepts_uint8() -> None:
    images, lights, _ = _quadratic_case((1.0, 1.0, 1.0))
    as_bytes = np.rint(images * 255.0).astype(np.uint8)
    ptm = fit_ptm_lrgb(as_bytes, lights)
    ref = fit_ptm_lrgb(as_bytes / 255.0, lights)
    assert np.array_equal(ptm.rgb, ref.rgb)
    assert np.abs(ptm.dequantized() - ref.dequantized()).max() <= ptm.scale.max() / 255.0


def test_quantisation_uses_full_range_without_clipping() -> None:
    rng = np.random.default_rng(3)
    a = rng.uniform(-50.0, 300.0, size=(5, 7, 6))
    a[..., 2] = 0.0  # constant coefficient
    q, scale, bias = quantize_coefficients(a)
    assert q.dtype == np.uint8 and scale.shape == (6,) and bias.shape == (6,)
    back = (q.astype(np.float64) - bias) * scale
    assert np.all(np.abs(back - a) <= scale / 2.0 + 1e-6)
    assert np.all((bias >= 0) & (bias <= 254))
    assert q[..., [0, 1, 3, 4, 5]].max() >= 253


@pytest.mark.parametrize(
    ("images_shape", "lights_shape"),
    [
        ((6, 4, 4), (6, 3)),  # no channel axis
        ((6, 4, 4, 4), (6, 3)),  # RGBA
        ((6, 4, 4, 3), (6, 2)),  # lights without z
        ((6, 4, 4, 3), (7, 3)),  # count mismatch
        ((5, 4, 4, 3), (5, 3)),  # too few lights
        ((6, 0, 4, 3), (6, 3)),  # empty
    ],
)
def test_fit_rejects_bad_shapes(
    images_shape: tuple[int, ...], lights_shape: tuple[int, ...]
) -> None:
    rng = np.random.default_rng(0)
    lights = rng.normal(size=lights_shape)
    if lights_shape[-1] == 3:
        lights[:, 2] = np.abs(lights[:, 2]) + 0.5
    with pytest.raises(ValueError):
        fit_ptm_lrgb(rng.random(images_shape), lights)


def test_fit_rejects_degenerate_lights_and_bad_dtype() -> None:
    images = np.full((12, 3, 3, 3), 0.5)
    same = np.tile([0.3, 0.2, 0.93], (12, 1))
    with pytest.raises(ValueError, match="determine"):
        fit_ptm_lrgb(images, same)
    with pytest.raises(ValueError, match="uint8 or floating"):
        fit_ptm_lrgb(images.astype(np.int16), demo_lights(12))
    with pytest.raises(ValueError, match="band_rows"):
        fit_ptm_lrgb(images, demo_lights(12), band_rows=0)
