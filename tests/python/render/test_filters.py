"""Screen-space box filters of the reference renderer against brute force."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
import pytest

from lanterna.tiler.render import box_filter, box_pass, f3, f5
from lanterna.tiler.render.filters import unsharp


def brute_box(q: npt.NDArray[np.float64], r: int) -> npt.NDArray[np.float64]:
    """The (2r+1)² mean with every index clamped to the array, one pixel at a time."""
    h, w = q.shape[:2]
    out = np.zeros_like(q)
    for y in range(h):
        for x in range(w):
            acc = np.zeros(q.shape[2:])
            for dy in range(-r, r + 1):
                for dx in range(-r, r + 1):
                    acc = acc + q[min(max(y + dy, 0), h - 1), min(max(x + dx, 0), w - 1)]
            out[y, x] = acc / (2 * r + 1) ** 2
    return out


@pytest.mark.parametrize("r", [1, 2])
@pytest.mark.parametrize("shape", [(7, 9), (6, 5, 3), (3, 2)])
def test_box_pass_equals_the_clamped_2d_mean(r: int, shape: tuple[int, ...]) -> None:
    q = np.random.default_rng(r).uniform(-1, 2, shape)
    np.testing.assert_allclose(box_pass(q, r), brute_box(q, r), atol=1e-5)


def test_f3_and_f5_are_repeated_box_passes() -> None:
    q = np.random.default_rng(0).uniform(0, 1, (12, 10))
    np.testing.assert_allclose(f3(q), brute_box(brute_box(q, 1), 1), atol=1e-5)
    five = q
    for _ in range(5):
        five = brute_box(five, 2)
    np.testing.assert_allclose(f5(q), five, atol=1e-5)


@pytest.mark.parametrize("filt", [f3, f5])
def test_filter_of_a_constant_is_the_constant_and_unsharp_is_the_identity(filt: object) -> None:
    q = np.full((9, 11, 3), 0.37, np.float32)
    assert callable(filt)
    blurred = filt(q)
    np.testing.assert_allclose(blurred, q, atol=1e-6)
    np.testing.assert_allclose(unsharp(q, blurred, 4.0), q, atol=1e-5)


def test_filter_keeps_a_linear_ramp_away_from_the_edges() -> None:
    ramp = np.tile(np.arange(30, dtype=np.float32), (20, 1))
    out = f5(ramp)
    np.testing.assert_allclose(out[:, 10:20], ramp[:, 10:20], atol=1e-4)
    # clamping at the edge pulls the first column up, the last down
    assert out[0, 0] > 0 and out[0, -1] < 29


def test_coverage_normalises_the_filter() -> None:
    rng = np.random.default_rng(3)
    q = rng.uniform(0, 1, (10, 12))
    a = np.zeros((10, 12))
    a[:, :6] = 1.0
    # a constant stays constant where the layer is drawn, whatever the coverage
    out = box_filter(np.full_like(q, 0.6), 2, 5, coverage=a)
    np.testing.assert_allclose(out[:, :6], 0.6, atol=1e-6)
    # F(q·a)/F(a) by hand; far from the coverage (F(a) = 0) q itself
    num, den = q * a, a
    for _ in range(2):
        num, den = brute_box(num, 1), brute_box(den, 1)
    out = box_filter(q, 1, 2, coverage=a)
    np.testing.assert_allclose(out[:, :8], num[:, :8] / den[:, :8], atol=1e-5)
    np.testing.assert_allclose(out[:, 10:], q[:, 10:], atol=1e-6)
    # full coverage is the plain filter
    np.testing.assert_allclose(box_filter(q, 1, 2, np.ones_like(q)), f3(q), atol=1e-6)


def test_filter_shapes_are_checked() -> None:
    with pytest.raises(ValueError):
        box_pass(np.zeros(5), 1)
    with pytest.raises(ValueError):
        box_filter(np.zeros((4, 4)), 1, 1, coverage=np.ones((3, 4)))
