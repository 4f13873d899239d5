"""The Ward kernel's vectorisable ``exp(−x)`` against numpy's ``exp``."""

from __future__ import annotations

import numba
import numpy as np
import numpy.typing as npt

from lanterna.tiler.fit.exp_kernel import X_MAX, exp_neg


@numba.njit(cache=False)
def _many(xs: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    out = np.empty_like(xs)
    for i in range(xs.size):
        out[i] = exp_neg(xs[i])
    return out


def _ulps(xs: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    ref = np.exp(-xs)
    return np.abs(_many(xs) - ref) / np.spacing(ref)


def test_within_one_ulp_on_the_ward_range() -> None:
    rng = np.random.default_rng(3)
    xs = np.concatenate([np.linspace(0.0, 50.0, 400_001), rng.uniform(0.0, 50.0, 400_000)])
    ulps = _ulps(xs)
    assert ulps.max() <= 1.0
    assert (ulps == 0).mean() > 0.85  # most values are numpy's to the bit


def test_edges_of_the_range_reduction() -> None:
    ln2 = np.log(2.0)
    k = np.arange(0, 1000, dtype=np.float64)
    xs = np.concatenate([k * ln2, k * ln2 + ln2 / 2, np.nextafter(k * ln2 + ln2 / 2, 0.0),
                         [0.0, 1e-300, 5e-324, X_MAX]])
    xs = xs[xs <= X_MAX]
    assert _ulps(xs).max() <= 1.0
    assert _many(np.array([0.0]))[0] == 1.0
    assert np.all(np.isfinite(_many(xs))) and np.all(_many(xs) > 0)
